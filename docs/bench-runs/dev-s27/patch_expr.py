"""Development: how many selection windows (episodes 6-9, 1 s) and all windows does each floor patch move by > 3 noise sigmas?"""
import sys, numpy as np
from voe.gap.bench import make_case, bench_scene
from voe.gap.truths import hide
from voe.gap.shooting import Shooter, make_windows
for seed in map(int, sys.argv[1:]):
    rng = np.random.default_rng(seed); scene = bench_scene('arena', rng); hidden = hide('floor_patch', scene, rng)
    case = make_case(np.random.default_rng(seed), 'floor_patch')
    a_, b_ = hidden.true['friction_region'][0][1:]
    mu = hidden.sim_scene.statics[1].friction
    out = []
    for which in (list(range(6, 10)), list(range(12))):
        wins = make_windows(case.episodes, which, 1.0)
        s0, s1 = Shooter(scene, case.episodes, 1e-3), Shooter(hidden.sim_scene, case.episodes, 1e-3)
        a, b = s0.simulate_many(wins, None, None), s1.simulate_many(wins, None, None)
        rms = np.array([float(np.sqrt(np.mean(((x - y) * s0.scale[None]) ** 2))) for x, y in zip(a, b)])
        out.append(f"{int((rms > 3e-3).sum())}/{len(wins)} (max {rms.max()*1e3:.1f} mm)")
    print(seed, f"patch [{a_:.2f}, {b_:.2f}] mu {mu:.2f}", 'selection', out[0], 'all', out[1], flush=True)
