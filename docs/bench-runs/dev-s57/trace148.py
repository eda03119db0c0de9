import sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig
s = int(sys.argv[1])
case = make_case(np.random.default_rng(s), "floor_patch", 1e-3, 12, 3.0, noise_kind="white")
f = GapFinder(max_effects=3, seed=s, config=GapConfig()).fit(case.scene, case.episodes)
print(s, f.verdict_, [(e["name"], {k: round(v, 3) for k, v in e["params"].items()}) for e in f.effects_])
print("true", case.true, "patch mu", [st.friction for st in case.sim_scene.statics[:3]])
print("scheme", f.problem_.split, "first look", f.first_look_)
print("located", [str(x)[:160] for x in f.located_][:8])
for r in f.search_.rounds if hasattr(f.search_, "rounds") else []:
    print("round", str(r)[:600])
for d in f.checked_.dropped:
    print("   drop", d["effect"], "|", d["reason"][:400])
print("fit", f.fit_)
