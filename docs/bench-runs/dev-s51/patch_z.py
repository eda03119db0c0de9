"""Where a bench floor patch's expressed windows stand against the location's threshold.

For each floor-patch case: the location's windows and threshold (``voe.gap.stages.locate_parts``, the
finder's own seed), each window's data z (max over bodies and coordinates), the replicate's, and how much
the patch moves the window's clean prediction (RMS, mm). Prints the expressed windows (> 3 sigma) sorted
by that, and the departure p.

    python patch_z.py SEED [SEED ...]
"""
import sys

import numpy as np

from voe.gap.bench import EXPRESSED_Z, bench_scene, make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.shooting import Shooter
from voe.gap.stages import GapConfig, locate_parts, prepare
from voe.gap.truths import hide, scene_kind

cfg = GapConfig()
for s in sys.argv[1:]:
    seed = int(s)
    rng = np.random.default_rng(seed)
    hidden = hide("floor_patch", bench_scene(scene_kind("floor_patch"), rng), rng)
    case = make_case(np.random.default_rng(seed), "floor_patch", 1e-3, 12, 3.0)
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
    _, finish = locate_parts(p, cfg, np.random.default_rng(seed))
    loc = finish()
    wins = loc.windows
    z = window_z(p.shooter, wins, p.sigma).max(axis=(1, 2))  # (W,)
    z_null = window_z(Shooter(p.scene, loc.null_episodes, p.substep, p.half), wins, p.sigma).max(axis=(1, 2))
    a = p.shooter.simulate_many(wins, None, None)
    b = Shooter(hidden.sim_scene, p.episodes, p.substep, p.half).simulate_many(wins, None, None)
    rms = np.array([float(np.sqrt(np.mean(((x - y) * p.shooter.scale[None]) ** 2))) for x, y in zip(a, b, strict=True)])
    ex = np.flatnonzero(rms > EXPRESSED_Z * 1e-3)
    mu = hidden.sim_scene.statics[1].friction
    print(f"{seed} mu {mu:.2f}: z_thr {loc.z_threshold:.1f} z_strong {loc.z_strong:.1f} departure_p {loc.departure_p:.3f} "
          f"located {len(loc.located)}; data z median {np.median(z):.1f}, replicate z median {np.median(z_null):.1f}")
    for i in ex[np.argsort(-rms[ex])]:
        w = wins[i]
        print(f"   ep {w.ep} k {w.k0}-{w.k1}: patch moves it {rms[i] * 1e3:6.1f} mm; data z {z[i]:6.1f} "
              f"(replicate {z_null[i]:6.1f}){'  LOCATED-level' if z[i] > loc.z_threshold else ''}", flush=True)
