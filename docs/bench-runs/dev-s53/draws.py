"""How much the departure test's tail p hangs on its replicates' draw (a look, for session 54): for each case, the
1-s location windows' tail p against R window-local clean replicates, over D independent draws, for R = 10 (the
finder's) and R = 30. Prints per case and R the median p, the share of draws below ALPHA / 2 (the tail test's
Bonferroni share) and the range.

    python draws.py D CASE [CASE ...]    CASE = bench case seed (e.g. 5025144); its bench seed is CASE // 1000
"""
import sys
import time

import numpy as np

from voe.gap.bench import make_case, plan
from voe.gap.departure import ALPHA, local_replicates, tail_p
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.shooting import make_windows
from voe.gap.stages import GapConfig, prepare

n_draws = int(sys.argv[1])
for case_seed in map(int, sys.argv[2:]):
    t0 = time.time()
    rows = plan(130, case_seed // 1000, 180, compound=8, outside=12, clean_kinds=("coloured", "white"))
    s, truth, nk, _ = rows[case_seed % 1000]
    case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=nk)
    config = GapConfig()
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
    windows = make_windows(p.episodes, list(range(len(p.episodes))), config.locate_window, bad_start=p.bad)
    z = window_z(p.shooter, windows, p.sigma).max(axis=(1, 2))  # (W,)
    out = []
    for r in (10, 30):
        ps = np.array([tail_p(z, local_replicates(p.shooter, windows, p.sigma, p.phi, np.random.default_rng([s, r, d]),
                                                  n=r, jitter=p.jitter)) for d in range(n_draws)])
        out.append(f"R {r:2d}: median {np.median(ps):.4f} below {np.mean(ps < ALPHA / 2):.2f} "
                   f"range {ps.min():.4f}-{ps.max():.4f}")
    print(f"{s} {truth:11s} {nk:8s} W {len(windows):2d} | " + " | ".join(out) + f" ({time.time() - t0:.0f} s)",
          flush=True)
