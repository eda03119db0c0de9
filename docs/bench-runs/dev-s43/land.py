import sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, _folded
from voe.gap.finder import ALL_EFFECTS
from voe.gap.fit import extend, scalar_grid

def setup(cid, truth):
    case = make_case(np.random.default_rng(cid), truth, 1e-3, 12, 3.0, noise_kind="white")
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
    return p, _folded(p, p.shooter, p.episodes, p.bad, cfg, cid).folds[0]

if sys.argv[1] == "010":
    p, f = setup(6219010, "restitution")
    eff = p.candidates["restitution"]
    lo, hi = eff.bounds(f.ctx); sc = eff.scale(f.ctx)
    print("bounds", lo, hi, "scale", sc, "starts", eff.starts(f.ctx))
    g = scalar_grid(eff, np.array([0.457]), lo, hi, sc)
    print("grid", np.round(g, 4))
    print("grid costs", [round(f.cost(eff, np.array([x])), 0) for x in g])
    xs = np.round(np.arange(0.05, 0.8, 0.025), 3)
    print("scan", [(x, round(f.cost(eff, np.array([x])), 0)) for x in xs])
    print("per-window cost at 0.097", np.round(f.window_costs(eff, np.array([0.097])), 0))
    print("per-window cost at 0.222", np.round(f.window_costs(eff, np.array([0.222])), 0))
    print("per-window cost at 0.457", np.round(f.window_costs(eff, np.array([0.457])), 0))
else:
    p, f = setup(6219041, "constant_acceleration")
    eff = p.candidates["constant_acceleration"]
    lo, hi = eff.bounds(f.ctx); sc = eff.scale(f.ctx)
    print("bounds", lo, hi, "scale", sc)
    e2, starts = extend(None, np.zeros(0), eff, f.ctx)
    sub = f._on(f.train[::3], f._weights[::3])
    print("starts", starts, "screen costs", [sub.cost(e2, s) for s in starts], "multi", eff.multi_start, eff.screen_all)
    for lab, x in [("start", starts[0]), ("fit", [0.5464, 0.4265]), ("truth", [0.6034, 0.3335]), ("fromtruth", [0.5805, 0.3181])]:
        x = np.asarray(x, float)
        print(lab, np.round(x, 4), round(f.cost(eff, x), 1), np.round(f.window_costs(eff, x), 0))
    f._memo = {}
    x, c = f._powell(eff, np.asarray(starts[0]), lo, hi, sc, f.config.max_nfev)
    print("powell from start", x, c)
