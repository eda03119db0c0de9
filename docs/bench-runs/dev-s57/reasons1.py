"""Each drop's reason in the first (three-way) look only."""
import sys
from dataclasses import replace
import numpy as np
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig
for s in map(int, sys.argv[2:]):
    case = make_case(np.random.default_rng(s), sys.argv[1], 1e-3, 12, 3.0, noise_kind="white")
    f = GapFinder(max_effects=3, seed=s, config=replace(GapConfig(), second_look=False)).fit(case.scene, case.episodes)
    print(s, f.verdict_, [(e["name"], {k: round(v, 3) for k, v in e["params"].items()}) for e in f.effects_])
    for d in f.checked_.dropped:
        print("   ", d["effect"], "|", d["reason"][:600])
    print("   true", case.true, flush=True)
