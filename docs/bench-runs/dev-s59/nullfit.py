"""One candidate fitted alone on the data's and on the clean replicate's folds, as round 1 fits it: params, gain,
and each selection window's RMSE ratio (development only).

    PYTHONPATH=<clone> python nullfit.py SEED TRUTH NOISE_KIND CANDIDATE
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.search import window_gain
from voe.gap.shooting import Shooter
from voe.gap.stages import GapConfig, _bad_starts, _folded

s, truth, kind, cand = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
config = GapConfig(second_look=False)
f = GapFinder(max_effects=3, seed=s, config=config).fit(case.scene, case.episodes)
p, loc = f.problem_, f.location_
null_eps = loc.null_episodes
null = _folded(p, Shooter(p.scene, null_eps, p.substep, p.half), null_eps, _bad_starts(p.scene, null_eps, p.half),
               config, s)
r = p.case_radius if hasattr(p, "case_radius") else case.scene.bodies[0].radius
for name, fitter, eps in (("data", f.search_.fitter, p.episodes), ("null", null, null_eps)):
    before = fitter.heldout_sse()
    res = fitter.fit_candidate(None, p.candidates[cand])
    ratios = np.sqrt(res.window_sse / before)
    print(f"{name}: {cand} params {np.round(res.params, 5).tolist()} gain {window_gain(before, res.window_sse):.4f} "
          f"train windows {sum(len(fo.train) for fo in fitter.folds)} selection windows {len(fitter.test)}")
    for w, q, b in zip(fitter.test, ratios, before, strict=True):
        ep = eps[w.ep]
        rolls = bool(np.all(np.abs(ep.pose[w.k0:w.k1 + 1, 0, 1] - r) < 0.005))
        print(f"   ep {w.ep:2d} t {ep.t[w.k0]:.2f} rolls {rolls!s:5s} rmse {1e3 * np.sqrt(b / (3 * 2 * (w.k1 - w.k0 + 1))):6.2f} mm ratio {q:.3f}")
