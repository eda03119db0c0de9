"""Print a case's search rounds (winner, group, basis) and what the check dropped (diagnosis only).

    python why.py SEED:TRUTH:NOISE
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder

seed, truth, nk = sys.argv[1].split(":")
case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
for r in f.search_.result.rounds:
    print("ROUND", r.winner, r.group, "|", r.basis)
print("DROPPED", f.checked_.dropped)
print("FIRST LOOK", f.first_look_)
print("VERDICT", f.verdict_, [e["name"] for e in f.effects_])
