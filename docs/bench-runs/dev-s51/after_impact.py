"""Would windows that start just after each impact see a sticky floor patch the location's windows miss?

For each case: the location's own windows (as ``locate_parts``), and windows of the same length starting at
the first clean sample after each impact stretch (``_bad_starts``); for each set, the data's window z and ten
window-local clean replicates' (``local_replicates``, fresh rng), the windows where the data exceeds every
replicate, and the tail test's p.

    python after_impact.py SEED:TRUTH [...]
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.departure import local_replicates, tail_p
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.shooting import Window, make_windows
from voe.gap.stages import GapConfig, prepare

cfg = GapConfig()
for arg in sys.argv[1:]:
    s, truth = arg.split(":")
    seed = int(s)
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0)
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
    base = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
    after = []
    for i, e in enumerate(p.episodes):
        bad = p.bad[i]
        n = int(round(cfg.locate_window / float(np.median(np.diff(e.t)))))
        for k in np.flatnonzero(bad[:-1] & ~bad[1:]) + 1:
            if k > p.half and k + int(0.8 * n) < len(e.t):
                after.append(Window(i, int(k), int(min(k + n, len(e.t) - 1))))
    for name, wins in (("location windows", base), ("after-impact windows", after)):
        z = window_z(p.shooter, wins, p.sigma).max(axis=(1, 2))
        loc = local_replicates(p.shooter, wins, p.sigma, p.phi, np.random.default_rng(seed + 1), jitter=p.jitter)
        top = np.flatnonzero(z > loc.max(axis=0))
        print(f"{seed} {truth} {name}: {len(wins)}, tail p {tail_p(z, loc):.4f}; data above every replicate in "
              f"{len(top)}: " + ", ".join(f"ep{wins[i].ep} k{wins[i].k0} z {z[i]:.1f}/{loc[:, i].max():.1f}"
                                          for i in top[np.argsort(-z[top])][:6]), flush=True)
