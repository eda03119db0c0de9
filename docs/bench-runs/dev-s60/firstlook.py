"""The first look alone (three-way split, no second look) of a bench case: rounds, drops, verdict (development only).

    PYTHONPATH=<clone> python firstlook.py SEED TRUTH NOISE_KIND
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
f = GapFinder(max_effects=3, seed=s, config=GapConfig(second_look=False)).fit(case.scene, case.episodes)
print(s, truth, kind, "verdict", f.verdict_, [(e["name"], e["params"]) for e in f.effects_])
for r in f.rounds_:
    print("  round", r.winner, r.group, r.threshold, {k: round(v, 4) for k, v in sorted(r.gains.items(), key=lambda kv: -kv[1])[:5]},
          "|", str(r.tie or "")[:400], "| lower", {k: round(v, 4) for k, v in sorted(r.lower.items(), key=lambda kv: -r.gains.get(kv[0], 0))[:3]},
          "| basis", r.basis[:600])
for d in f.checked_.dropped:
    print("  drop", d["effect"], "|", d["reason"][:700])
