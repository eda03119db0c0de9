"""A region candidate's fit with its right edge x1 moved (the rest at the fit): fitting cost (the fit's own
robust cost) and selection gain with its 5 % bootstrap quantile (development only).

    PYTHONPATH=<clone> python edge.py SEED TRUTH NOISE_KIND CANDIDATE
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.search import gain_lower_bound, window_gain
from voe.gap.stages import GapConfig, _folded, prepare

s, truth, kind, cand = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
config = GapConfig(second_look=False)
p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
data = _folded(p, p.shooter, p.episodes, p.bad, config, s)
eff = p.candidates[cand]
res = data.fit_candidate(None, eff)
fit = np.asarray(res.fold_params[0], dtype=float)
fitter = data.folds[0]
before = data.heldout_sse()
print(s, truth, "true", case.true, "fit", np.round(fit, 4).tolist(), flush=True)
for x1 in [fit[1] + 0.1, 0.8, 1.0, 1.1, 1.2, 1.3, 1.5, 2.0, 2.5, 3.0, fit[2]]:
    q = fit.copy()
    q[2] = max(x1, fit[1] + 0.05)
    after = data.heldout_sse(res.effect, (q,))
    print(f"  x1 {q[2]:.3f}: fitting cost {fitter.cost(res.effect, q):.1f}  selection gain {window_gain(before, after):+.4f} "
          f"5 % quantile {gain_lower_bound(before, after):+.4f}", flush=True)
after = data.heldout_sse(res.effect, (fit,))
wins = data.test
print("per selection window at the fit: episode, t0, RMSE before -> after (mm)")
for w, b, a in zip(wins, before, after):
    n = (w.k1 - w.k0 + 1) * 6
    print(f"  ep {w.ep} t {p.episodes[w.ep].t[w.k0]:.2f}-{p.episodes[w.ep].t[w.k1]:.2f}: {1e3 * np.sqrt(b / n):.2f} -> {1e3 * np.sqrt(a / n):.2f}")
