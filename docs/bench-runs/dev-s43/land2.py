import sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, _folded
from voe.gap.fit import extend, scalar_grid
cid, truth, nk = int(sys.argv[1]), sys.argv[2], sys.argv[3]
case = make_case(np.random.default_rng(cid), truth, 1e-3, 12, 3.0, noise_kind=nk)
cfg = GapConfig()
p = prepare(case.scene, case.episodes, (truth,), cfg)
f = _folded(p, p.shooter, p.episodes, p.bad, cfg, cid).folds[0]
eff = p.candidates[truth]
lo, hi = eff.bounds(f.ctx); sc = eff.scale(f.ctx)
e2, starts = extend(None, np.zeros(0), eff, f.ctx)
print("true", case.params, "bounds", lo, hi, "scale", sc, "starts", starts)
for s in starts:
    g = scalar_grid(eff, s, lo, hi, sc)
    print("grid", np.round(g, 4), [round(f.cost(eff, np.array([x])), 0) for x in g])
a, b = float(sys.argv[4]), float(sys.argv[5])
xs = np.linspace(a, b, 25)
print("scan", [(round(x, 4), round(f.cost(eff, np.array([x])), 0)) for x in xs])
