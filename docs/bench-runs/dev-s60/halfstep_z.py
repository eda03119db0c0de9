"""Window z of clean cases' recordings against the nominal model (the locate stage's statistic), with and without
the half-step start-velocity correction (``halfstep.patch`` applied to the clone; development only).

    PYTHONPATH=<patched clone> python halfstep_z.py SEED0 N [white|coloured]
"""
import sys

import numpy as np

import voe.gap.shooting as S
from voe.gap.bench import make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.shooting import make_windows
from voe.gap.stages import GapConfig, prepare

s0, n = int(sys.argv[1]), int(sys.argv[2])
kind = sys.argv[3] if len(sys.argv) > 3 else "white"
config = GapConfig()
rows = {None: [], 1: []}
for s in range(s0, s0 + n):
    case = make_case(np.random.default_rng(s), "none", 1e-3, 12, 3.0, noise_kind=kind)
    for mode in (None, 1):
        p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
        S.HALF_STEP = None if mode is None else p.substep
        sh = S.Shooter(p.scene, p.episodes, p.substep, p.half)
        wins = make_windows(p.episodes, list(range(len(p.episodes))), config.locate_window, bad_start=p.bad)
        z = window_z(sh, wins, p.sigma).max(axis=(1, 2))  # (W,)
        rows[mode].append(z)
    S.HALF_STEP = None
    a, b = rows[None][-1], rows[1][-1]
    print(f"{s} {'joints' if case.scene.joints else 'arena'}: median z {np.median(a):.2f} -> {np.median(b):.2f}, "
          f"max {a.max():.1f} -> {b.max():.1f}", flush=True)
a, b = np.concatenate(rows[None]), np.concatenate(rows[1])
print(f"all {a.size} windows: median z {np.median(a):.2f} -> {np.median(b):.2f}; 95th pct {np.quantile(a, 0.95):.1f} -> "
      f"{np.quantile(b, 0.95):.1f}; above 5: {(a > 5).sum()} -> {(b > 5).sum()}")
