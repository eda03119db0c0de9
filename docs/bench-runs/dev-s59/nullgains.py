"""Round 1 of a case: the data's candidate gains against the null replicate's (development only).

    PYTHONPATH=<clone> python nullgains.py SEED TRUTH NOISE_KIND
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
f = GapFinder(max_effects=3, seed=s, config=GapConfig(second_look=False)).fit(case.scene, case.episodes)
r0 = f.rounds_[0]
print(s, "data round 1 threshold", r0.threshold, {k: round(v, 4) for k, v in sorted(r0.gains.items(), key=lambda kv: -kv[1])[:5]})
for i, n in enumerate(f.search_.null):
    print("  null round", i + 1, "threshold", round(n.threshold, 4),
          {k: round(v, 4) for k, v in sorted(n.gains.items(), key=lambda kv: -kv[1])[:5] if np.isfinite(v)})
print("  null episodes", len(f.location_.null_episodes), "selection windows (data)", len(f.search_.fitter.test))
