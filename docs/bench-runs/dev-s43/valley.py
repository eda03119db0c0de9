"""Is a wrong fit an optimiser failure (truth cheaper on the training cost) or the objective's?"""
import sys, time
import numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, _folded
from voe.gap.finder import ALL_EFFECTS
from voe.gap.effects import EFFECTS
from voe.gap.fit import extend

def main(cid, truth, name, pts):
    case = make_case(np.random.default_rng(cid), truth, 1e-3, 12, 3.0, noise_kind="white")
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
    ff = _folded(p, p.shooter, p.episodes, p.bad, cfg, cid)
    f = ff.folds[0]
    eff = p.candidates[name]
    print(cid, truth, "true", case.true, "candidate", name, "n train", len(f.train), "n sel", len(f.test))
    base = f.heldout_sse(None, None).sum()
    print(" train cost nominal", round(f.cost(None, None), 2), "sel sse nominal", base)
    for lab, x in pts:
        x = np.asarray(x, float)
        sse = f.heldout_sse(eff, x)
        ratios = np.sqrt(sse / f.heldout_sse(None, None))
        gain = 1 - float(np.exp(np.mean(np.log(np.maximum(ratios, 1e-12)))))
        print(f" {lab:10s} x={np.round(x,4)} train cost {f.cost(eff, x):10.2f} sel gain {gain:.4f}")
    t0 = time.time()
    e2, starts = extend(None, np.zeros(0), eff, f.ctx)
    print(" starts", [np.round(s, 3) for s in starts])
    r = f.fit(e2, starts)
    print(f" refit from own starts: x={np.round(r.params,4)} cost {r.train_cost:.2f} ({time.time()-t0:.0f}s)")
    r = f.fit(e2, [np.asarray(pts[1][1], float)])
    print(f" fit from truth: x={np.round(r.params,4)} cost {r.train_cost:.2f}")

if sys.argv[1] == "041":
    main(6219041, "constant_acceleration", "constant_acceleration", [("fitted", [0.5464, 0.4265]), ("truth", [0.60336482, 0.33354326])])
else:
    main(6219010, "restitution", "restitution", [("fitted", [0.097]), ("truth", [0.22235277]), ("region-e", [0.3204])])
