"""The located stage alone (no search): departure p, located count, and the windows a relative location would
list (data window z above every one of its own window-local clean replicates and above z_min), per case.

    python rel_locate.py SEED [SEED ...]   -> one line per out-of-library case (138-149) and extra clean case 150-329
"""
import sys, time
import numpy as np
from voe.gap.bench import plan
from voe.gap.bench import make_case
from voe.gap.departure import departure_p, local_replicates
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import locate, window_z
from voe.gap.shooting import Shooter, make_windows
from voe.gap.stages import GapConfig, prepare
from voe.gap.synth import null_like  # noqa: F401 (locate_parts' replicate)
from voe.gap.stages import locate_parts

cfg = GapConfig()
for s in map(int, sys.argv[1:]):
    rows = plan(130, s, 180, compound=8, outside=12, clean_kinds=("coloured", "white"))
    for seed, truth, nk, role in rows[138:330]:
        t0 = time.time()
        case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
        p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
        rng = np.random.default_rng(seed)
        null_eps, _ = locate_parts(p, cfg, rng)  # the same draws as the finder's first look
        windows = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
        z_null = window_z(Shooter(p.scene, null_eps, p.substep, p.half), windows, p.sigma).max(axis=(1, 2))
        z_thr = float(max(cfg.z_min, np.quantile(z_null, 0.95)))
        zw = window_z(p.shooter, windows, p.sigma)
        located = locate(p.shooter, windows, zw, z_thr)
        local = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, jitter=p.jitter)
        z = zw.max(axis=(1, 2))
        dp = departure_p(z, z_null, local)
        rel = int(np.sum((z > local.max(axis=0)) & (z > cfg.z_min)))
        print(f"{seed} {truth:11s} {nk:8s} dep_p {dp:.4f} z_thr {z_thr:6.1f} located {len(located):2d} rel {rel:2d} "
              f"({time.time() - t0:.0f} s)", flush=True)
