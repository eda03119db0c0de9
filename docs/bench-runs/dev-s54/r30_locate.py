"""The locate stage alone (no search), as the finder draws it, with twenty more window-local clean replicates
drawn after the finder's ten (from the same generator, which the finder does not use after them): per case the
signed-rank p, the tail p against the ten (t10) and against all thirty (t30, drawn when t10 < 0.5), the count of
stretches above the first bar and of windows the second bar would locate (ten replicates).

    python r30_locate.py SEED [SEED ...]  -> one line per out-of-library case (138-149) and extra clean case 150-329
"""
import sys, time
import numpy as np
from voe.gap.bench import plan, make_case
from voe.gap.departure import _signed_rank_p, local_replicates, tail_p
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import locate, window_z
from voe.gap.shooting import Shooter, make_windows
from voe.gap.stages import GapConfig, prepare, locate_parts

cfg = GapConfig()
for s in map(int, sys.argv[1:]):
    rows = plan(130, s, 180, compound=8, outside=12, clean_kinds=("coloured", "white"))
    for seed, truth, nk, role in rows[138:330]:
        t0 = time.time()
        case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
        p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
        rng = np.random.default_rng(seed)
        null_eps, _ = locate_parts(p, cfg, rng)  # the same draws as the finder's
        windows = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
        z_null = window_z(Shooter(p.scene, null_eps, p.substep, p.half), windows, p.sigma).max(axis=(1, 2))
        z_thr = float(max(cfg.z_min, np.quantile(z_null, 0.95)))
        zw = window_z(p.shooter, windows, p.sigma)
        located = locate(p.shooter, windows, zw, z_thr)
        local = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, jitter=p.jitter)  # (10, W)
        z = zw.max(axis=(1, 2))
        sr, t10 = _signed_rank_p(z, z_null), tail_p(z, local)
        t30 = float("nan")
        if t10 < 0.5:
            more = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, 20, jitter=p.jitter)  # (20, W)
            t30 = tail_p(z, np.vstack([local, more]))
        rel = int(np.sum((z > local.max(axis=0)) & (z > cfg.z_min)))
        print(f"{seed} {truth:11s} {nk:8s} sr {sr:.4f} t10 {t10:.4f} t30 {t30:.4f} z_thr {z_thr:6.1f} "
              f"located {len(located):2d} rel {rel:2d} ({time.time() - t0:.0f} s)", flush=True)
