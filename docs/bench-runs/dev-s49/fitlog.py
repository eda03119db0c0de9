"""Log Fitter.fit calls for a multi-part effect whose newest part is NAME: start, result, full-train cost at each."""
import sys
import numpy as np
import voe.gap.fit as fm
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder
seed, truth, nk = sys.argv[1].split(":"); seed = int(seed); name = sys.argv[2]
extra = [np.array([float(v) for v in s.split(",")]) for s in sys.argv[3:]]
orig = fm.Fitter.fit
def fit(self, effect, starts=None, max_nfev=None):
    res = orig(self, effect, starts, max_nfev)
    if len(effect.parts) >= 2 and effect.parts[-1].name == name:
        full = self.unfocused() if hasattr(self, "unfocused") else self
        s = [np.clip(x, *effect.bounds(self.ctx)) for x in (starts or effect.starts(self.ctx))]
        print("FIT", [p.name for p in effect.parts], "ntrain", len(self.train), "pool", len(self.pool or []),
              "\n  starts", [(np.round(x, 4).tolist(), round(self.cost(effect, x), 1)) for x in s],
              "\n  result", np.round(res.params, 4).tolist(), round(res.train_cost, 1), round(self.cost(effect, res.params), 1),
              "\n  extra", [(x.tolist(), round(self.cost(effect, x), 1)) for x in extra if x.size == effect.n_params], flush=True)
    return res
fm.Fitter.fit = fit
case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
print("nominal elasticity", [b.elasticity for b in case.scene.bodies])
f = GapFinder(max_effects=3, seed=seed, config=GapConfig(), n_jobs=1).fit(case.scene, case.episodes) if "n_jobs" in GapFinder.__init__.__code__.co_varnames else GapFinder(max_effects=3, seed=seed, config=GapConfig()).fit(case.scene, case.episodes)
print(f.verdict_, [e["name"] for e in f.effects_])
