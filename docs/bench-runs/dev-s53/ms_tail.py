"""The departure test's tail p at other window lengths (a look): for each case, ``tail_p`` of the data's window z
against ten window-local clean replicates of the same windows, for windows of 0.25, 0.5 and 1 s (1 s: the
finder's), the replicates drawn from one seed per case (not the finder's draws).

    python ms_tail.py CASE [CASE ...]    CASE = bench case seed (e.g. 5025144); its bench seed is CASE // 1000
"""
import sys
import time

import numpy as np

from voe.gap.bench import make_case, plan
from voe.gap.departure import local_replicates, tail_p
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.shooting import make_windows
from voe.gap.stages import GapConfig, prepare

LENGTHS = (0.25, 0.5, 1.0)
for case_seed in map(int, sys.argv[1:]):
    t0 = time.time()
    rows = plan(130, case_seed // 1000, 180, compound=8, outside=12, clean_kinds=("coloured", "white"))
    s, truth, nk, _ = rows[case_seed % 1000]
    case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=nk)
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, GapConfig())
    out = []
    for length in LENGTHS:
        rng = np.random.default_rng([s, int(1000 * length)])
        windows = make_windows(p.episodes, list(range(len(p.episodes))), length, bad_start=p.bad)
        z = window_z(p.shooter, windows, p.sigma).max(axis=(1, 2))  # (W,)
        local = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, jitter=p.jitter)  # (R, W)
        above = int(np.sum(z > local.max(axis=0)))
        out.append(f"{length:g}s W {len(windows):3d} above {above:3d} p {tail_p(z, local):.4f}")
    print(f"{s} {truth:11s} {nk:8s} " + " | ".join(out) + f" ({time.time() - t0:.0f} s)", flush=True)
