"""Selection gains of hand-set models on a bench case (diagnosis only)."""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.finder import ALL_EFFECTS
from voe.gap.search import gain_lower_bound, window_gain
from voe.gap.stages import GapConfig, _folded, prepare

seed, truth = int(sys.argv[1]), sys.argv[2]
models = [m for m in sys.argv[3:]]  # "name=p1,p2;name2=..." ; first is the reference
case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind="white")
print("true", case.true)
cfg = GapConfig()
p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
data = _folded(p, p.shooter, p.episodes, p.bad, cfg, seed)
def build(spec):
    if spec == "none":
        return None, None
    parts, ps = [], []
    for item in spec.split(";"):
        name, vals = item.split("=")
        body = None
        if "[" in name:
            name, body = name[:-1].split("[")
        cls = EFFECTS.get(name)
        parts.append(cls(bodies=(body,)) if body else cls())
        ps += [float(v) for v in vals.split(",")]
    eff = parts[0] if len(parts) == 1 else EffectSum(parts)
    return eff, tuple(np.array(ps) for _ in data.folds)
ref = None
for m in models:
    eff, fp = build(m)
    sse = data.heldout_sse(eff, fp)
    if ref is None:
        ref = sse
        print(f"{m:60s} ref  rmse {np.sqrt(sse.mean()):.5f}")
        continue
    print(f"{m:60s} gain {window_gain(ref, sse):.4f} lower {gain_lower_bound(ref, sse):.4f}")
