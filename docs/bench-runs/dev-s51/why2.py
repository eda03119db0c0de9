"""A case's rounds (winner, group, basis), the check's drops, both looks' departure p and located count.

    python why2.py SEED:TRUTH:NOISE
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder

seed, truth, nk = sys.argv[1].split(":")
case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig(), n_jobs=1).fit(case.scene, case.episodes)
print("HIDDEN", getattr(case, "hidden", None), getattr(case, "params", None))
for r in f.search_.result.rounds:
    print("ROUND", r.winner, r.group, "|", r.basis)
    top = sorted(r.gains, key=lambda k: -r.gains[k])[:4]
    print("   before", round(r.before * 1e3, 2), "mm; threshold", None if r.threshold is None else round(r.threshold, 4),
          "; top gains", [(k, round(r.gains[k], 4), round(r.lower.get(k, float("nan")), 4)) for k in top])
print("DROPPED", f.checked_.dropped)
print("FIRST LOOK", f.first_look_)
loc = f.location_
print("LOCATION departure_p", loc.departure_p, "z_threshold", loc.z_threshold, "located", len(f.located_))
print("VERDICT", f.verdict_, [e["name"] for e in f.effects_])
