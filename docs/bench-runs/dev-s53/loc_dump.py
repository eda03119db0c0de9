"""Print each case's location (located stretches, departure p) as JSON lines: compare two checkouts."""
import json, sys
import numpy as np
from voe.gap.bench import make_case, plan
from voe.gap.finder import ALL_EFFECTS
from voe.gap.stages import GapConfig, locate_step, prepare
rows = plan(130, 7241, 180, compound=8, outside=12, clean_kinds=("coloured", "white"))
for seed in map(int, sys.argv[1:]):
    s, truth, nk, _ = rows[seed - 7241000]
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, GapConfig())
    loc = locate_step(p, GapConfig(), np.random.default_rng(seed))
    print(json.dumps({"seed": seed, "p": loc.departure_p, "located": loc.located}), flush=True)
