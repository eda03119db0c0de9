"""One window of a bench case shot from the recording's estimated start and from the noise-free recording's
(development only): is the window's error start-state error, and which part of the start matters?

    PYTHONPATH=<clone> python firstwin.py SEED TRUTH NOISE_KIND EPISODE K0 K1
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.shooting import Shooter, Window, local_state
from voe.gap.stages import GapConfig, prepare

s, truth, kind, e, k0, k1 = sys.argv[1], sys.argv[2], sys.argv[3], *map(int, sys.argv[4:7])
s = int(s)
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
clean = make_case(np.random.default_rng(s), truth, 0.0, 12, 3.0, noise_kind=kind)
p = prepare(case.scene, case.episodes, ALL_EFFECTS, GapConfig())
sh = Shooter(case.scene, case.episodes, p.substep, p.half)
w = Window(e, k0, k1)
est = sh.initial(e, k0)
true = local_state(clean.episodes[e], k0, 2)
print("half", p.half, "start pose est", np.round(est[0], 4).tolist(), "true", np.round(true[0], 4).tolist())
print("start vel est", np.round(est[1], 3).tolist(), "true", np.round(true[1], 3).tolist())
for name, (pose, vel) in (("estimated", est[:2]), ("true", true[:2]), ("true pose, est vel", (true[0], est[1])),
                          ("est pose, true vel", (est[0], true[1]))):
    sh._ic[(e, k0)] = (pose, vel, est[2])
    sh._memo.clear()
    r = sh.residual(w, None, None)  # (n, B, 3)
    print(f"  {name:20s}: RMS per body (mm) {np.round(1e3 * np.sqrt((r ** 2).mean(axis=(0, 2))), 2).tolist()}, "
          f"max |x| ball {1e3 * np.abs(r[:, 0, 0]).max():.1f} box {1e3 * np.abs(r[:, 1, 0]).max():.1f}")
