"""First look only (GapConfig(second_look=False)): Trace one bench case of a finished run (development only): what located, what the departure test said,
each round, each drop and the fit.

    PYTHONPATH=<clone> python trace.py SEED TRUTH NOISE_KIND
"""
import sys
import time

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
t0 = time.time()
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
f = GapFinder(max_effects=3, seed=s, config=GapConfig(second_look=False)).fit(case.scene, case.episodes)
print(s, truth, kind, "verdict", f.verdict_, [(e["name"], {k: round(v, 4) for k, v in e["params"].items()})
                                              for e in f.effects_], f"{time.time() - t0:.0f} s")
print("split", f.problem_.split.scheme, "first look", f.first_look_)
print("z_threshold", round(f.z_threshold_, 3), "z_strong", round(f.z_strong_, 3),
      "departure_p", f.location_.departure_p)
for x in f.located_:
    print("  located", {k: (round(v, 3) if isinstance(v, float) else v) for k, v in x.items()})
for r in f.rounds_:
    print("  round", r.winner, r.group, r.threshold,
          {k: round(v, 4) for k, v in sorted(r.gains.items(), key=lambda kv: -kv[1])[:4]}, "|", str(r.tie or "")[:300])
for d in f.checked_.dropped:
    print("  drop", d["effect"], "|", d["reason"][:500])
print("  fit", {k: v for k, v in f.fit_.items() if k not in ("metric",)})
print("  explanation", f.explanation_[:1500])
