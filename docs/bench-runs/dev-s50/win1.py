"""Per-window fitting costs of a global part and its region form in round 0 (diagnosis only).

    python win1.py SEED:TRUTH:NOISE GLOBAL REGION c1 c2 ...

Prints, for GLOBAL's first one-part fit, every training window's soft-L1 cost at each given value
and at the fit, and for REGION's first fit the same at its fitted parameters; stops after both.
"""
import sys

import numpy as np

import voe.gap.fit as fm
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder

seed, truth, nk = sys.argv[1].split(":")
glob, reg = sys.argv[2], sys.argv[3]
vals = [float(v) for v in sys.argv[4:]]
orig = fm.Fitter.fit
seen: dict[str, tuple] = {}


def fit(self, effect, starts=None, max_nfev=None):
    res = orig(self, effect, starts, max_nfev)
    if len(effect.parts) == 1 and effect.parts[0].name in (glob, reg) and effect.parts[0].name not in seen:
        name = effect.parts[0].name
        ids = [(w.ep, w.k0, w.k1) for w in self.train]
        rows = {"fit": self.window_costs(effect, res.params)}
        if name == glob:
            for v in vals:
                rows[f"c={v}"] = self.window_costs(effect, np.array([v]))
        rows["none"] = self.window_costs(None, None)
        seen[name] = (ids, rows, np.round(res.params, 4).tolist(), res.train_cost)
        print("FIT", name, "params", seen[name][2], "train_cost", round(res.train_cost, 1), "windows", len(ids),
              flush=True)
        print("  window", *(f"{k:>11s}" for k in rows), sep=" ")
        for i, w in enumerate(ids):
            print(f"  {str(w):16s}", *(f"{rows[k][i]:11.1f}" for k in rows))
        print("  tail-sum", *(f"{np.sum(fm.window_tail(rows[k], self.config.window_knee)):11.1f}" for k in rows))
        if len(seen) == 2:
            sys.exit(0)
    return res


fm.Fitter.fit = fit
case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
print("truth", case.truth if hasattr(case, "truth") else truth, flush=True)
GapFinder(max_effects=1, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
