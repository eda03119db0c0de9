"""Log one-part fits of NAME: grid costs, result, and the cost at given values (diagnosis only)."""
import sys
import numpy as np
import voe.gap.fit as fm
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder
seed, truth, nk = sys.argv[1].split(":"); seed = int(seed); name = sys.argv[2]
vals = [float(v) for v in sys.argv[3:]]
orig = fm.Fitter.fit
def fit(self, effect, starts=None, max_nfev=None):
    res = orig(self, effect, starts, max_nfev)
    if len(effect.parts) == 1 and effect.parts[0].name == name:
        print("FIT", name, "ntrain", len(self.train), "starts", [np.round(s, 4).tolist() for s in (starts or [])],
              "result", np.round(res.params, 4).tolist(), round(res.train_cost, 1), "grid_end", res.grid_end,
              "\n  at", [(v, round(self.cost(effect, np.array([v])), 1)) for v in vals], flush=True)
    return res
fm.Fitter.fit = fit
case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
f = GapFinder(max_effects=1, seed=seed, config=GapConfig()).fit(case.scene, case.episodes)
print(f.verdict_, [e["name"] for e in f.effects_])
