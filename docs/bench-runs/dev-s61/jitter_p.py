"""Departure p of clean jittered cases (the locate stage alone, the finder's own draws; development only).

    PYTHONPATH=<clone> python jitter_p.py SEED [SEED ...]

Prints one line per case: seed, whether the jitter model opened, the departure p, the located threshold.
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig, locate_step, prepare

for seed in map(int, sys.argv[1:]):
    case = make_case(np.random.default_rng(seed), "none", noise_kind="jitter")
    p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, GapConfig())
    loc = locate_step(p, GapConfig(), np.random.default_rng(seed))
    print(seed, p.jitter is not None, f"{loc.departure_p:.4g}", f"{loc.z_threshold:.2f}", len(loc.located), flush=True)
