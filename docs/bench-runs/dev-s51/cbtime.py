import time, numpy as np
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.rollout import run_many
from voe.gap.shooting import Shooter, Window
case = make_case(np.random.default_rng(1), "none", episodes=4, duration=3.0)
sh = Shooter(case.scene, case.episodes, 1e-3)
wins = [Window(ep, k0, k0 + 100) for ep in range(4) for k0 in (0, 100, 199)]
st = [sh.initial(w.ep, w.k0)[:2] for w in wins]; tm = [case.episodes[w.ep].t[w.k0:w.k1 + 1] for w in wins]
for name, p in (("friction_region", [1.5, -5, 5]), ("restitution_region", [0.2, -5, 5])):
    eff = EFFECTS.get(name)()
    best = 1e9
    for _ in range(7):
        t0 = time.process_time(); run_many(case.scene, st, tm, 1e-3, eff, np.array(p)); best = min(best, time.process_time() - t0)
    out = run_many(case.scene, st, tm, 1e-3, eff, np.array(p))
    print(name, f"{best*1e3:.1f} ms", float(sum(o.sum() for o in out)).hex())
t0 = time.process_time(); run_many(case.scene, st, tm, 1e-3, None, None); print("nominal", f"{(time.process_time()-t0)*1e3:.1f} ms")
