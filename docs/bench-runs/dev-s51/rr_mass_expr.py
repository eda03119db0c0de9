"""How many windows each part of a compound truth is expressed in (the bench's 3-sigma rule, on the location's
windows over every episode): the model with both parts against the model with the other part alone.

    python rr_mass_expr.py SEED:TRUTH [...]
"""
import sys

import numpy as np

from voe.gap.bench import EXPRESSED_Z, make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.shooting import Shooter, choose_half, make_windows
from voe.gap.stages import GapConfig

cfg = GapConfig()
for arg in sys.argv[1:]:
    s, truth = arg.split(":")
    case = make_case(np.random.default_rng(int(s)), truth, 1e-3, 12, 3.0)
    eps = case.episodes
    wins = make_windows(eps, list(range(len(eps))), cfg.locate_window)
    sh = Shooter(case.scene, eps, 1e-3, choose_half(case.scene, eps, wins, 1e-3))
    parts = [(n, EFFECTS.get(n)(bodies=tuple(b) if b else None), np.asarray(p, dtype=float)) for n, (p, b) in case.true.items()]
    both = sh.simulate_many(wins, EffectSum(tuple(e for _, e, _ in parts)), np.concatenate([p for _, _, p in parts]))
    line = []
    for i, (n, e, p) in enumerate(parts):
        others = [x for j, x in enumerate(parts) if j != i]
        _, eo, po = others[0]
        alone = sh.simulate_many(wins, eo, po)
        rms = np.array([float(np.sqrt(np.mean(((x - y) * sh.scale[None]) ** 2))) for x, y in zip(both, alone, strict=True)])
        line.append(f"{n} {np.round(p, 4).tolist()} expressed in {int((rms > EXPRESSED_Z * 1e-3).sum())}/{len(wins)} "
                    f"(max {rms.max() * 1e3:.1f} mm)")
    print(s, truth, "|", "; ".join(line), flush=True)
