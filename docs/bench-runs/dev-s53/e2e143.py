import json, sys, numpy as np, tempfile
from pathlib import Path
from voe.gap.bench import make_case, plan
from voe.gap.finder import GapFinder
seed = int(sys.argv[1])
rows = plan(130, 7241, 180, compound=8, outside=12, clean_kinds=("coloured", "white"))
s, truth, nk, _ = rows[seed - 7241000]
case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
f = GapFinder(seed=seed).fit(case.scene, case.episodes)
print(truth, nk, f.verdict_, [e["name"] for e in f.effects_], f.location_.departure_p)
print(f.explanation_)
print(json.dumps(f.located_[:3], indent=1))
from voe.gap.report import markdown
print(markdown(f, []))
