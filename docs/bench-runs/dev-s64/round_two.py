# Round 2 of bench/gap_speed.py's case by hand (session 64): round 1's drag fitted and accepted as the search does,
# then four round-2 candidates on top, the drag alone at nearby values, and drag + constant_acceleration. One process.
# Run: PYTHONPATH=<clone> python round_two.py
import time, numpy as np
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.stages import GapConfig, prepare, _folded
from voe.gap.search import window_gain, accept
t0=time.process_time()
case = make_case(np.random.default_rng(3), "quadratic_drag", episodes=20, duration=5.0)
cfg = GapConfig()
effects = tuple(k for k in EFFECTS if k != "none")
p = prepare(case.scene, case.episodes, effects, cfg)
data = _folded(p, p.shooter, p.episodes, p.bad, cfg, 0)
before = data.heldout_sse()
c = p.candidates
r1 = data.fit_candidate(None, c["quadratic_drag"]); g1 = window_gain(before, r1.window_sse)
acc = accept(data, r1, g1, before); ga = window_gain(before, acc.window_sse)
print("round1 qd", [np.round(x,4) for x in r1.fold_params], f"gain {g1:.4f}; accepted {[np.round(x,4) for x in acc.fold_params]} gain {ga:.4f}", f"cpu {time.process_time()-t0:.1f}", flush=True)
b2 = acc.window_sse
ref = data.refine(acc); print("refine again", [np.round(x,4) for x in ref.fold_params], f"gain over acc {window_gain(b2, ref.window_sse):.4f}", flush=True)
for k in ["constant_acceleration", "linear_drag", "friction", "mass[ball]"]:
    if k not in c: continue
    r = data.fit_candidate(acc, c[k])
    print(k, [np.round(x,4) for x in r.fold_params], f"gain over acc {window_gain(b2, r.window_sse):.4f}", f"cpu {time.process_time()-t0:.1f}", flush=True)
from voe.gap.effects.base import EffectSum
qd = c["quadratic_drag"]
print("qd alone at c:")
for v in [0.1180, 0.1184, 0.1190, 0.1192, 0.1196, 0.1200, 0.1209]:
    s = data.heldout_sse(qd, (np.array([v]),)); print(f"  {v:.4f} gain over acc {window_gain(b2, s):.4f}", flush=True)
ca = EffectSum((qd, c["constant_acceleration"]))
for prm in [[0.1184,0.0002,-0.0036],[0.1184,0,0],[0.1196,0,0]]:
    s = data.heldout_sse(ca, (np.array(prm),)); print("  qd+ca", prm, f"gain over acc {window_gain(b2, s):.4f}", flush=True)
