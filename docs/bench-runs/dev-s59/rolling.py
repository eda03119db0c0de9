"""A clean case's rolling windows: residual of the nominal simulation per variable, from the window's estimated
start state and from the clean (noise-free) recording's start state (development only).

    PYTHONPATH=<clone> python rolling.py SEED
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.recordings import Episode
from voe.gap.shooting import Shooter, Window

s = int(sys.argv[1])
rng = np.random.default_rng(s)
case = make_case(rng, "none", 1e-3, 12, 3.0, noise_kind="white")
clean_case = make_case(np.random.default_rng(s), "none", 0.0, 12, 3.0, noise_kind="white")
for name, eps in (("recorded", case.episodes), ("noise-free", clean_case.episodes)):
    sh = Shooter(case.scene, eps, 1e-3)
    for e, (k0, k1) in ((6, (141, 241)), (7, (189, 289)), (9, (139, 239)), (9, (214, 300))):
        ep = eps[e]
        k1 = min(k1, len(ep.t) - 1)
        r = sh.residual(Window(e, k0, k1), None, None)  # (T, B, 3)
        rms = np.sqrt((r ** 2).mean(axis=0))  # (B, 3)
        pose0, vel0, _ = sh.initial(e, k0)
        print(f"{name:10s} ep {e} t {ep.t[k0]:.2f} ball rms x {1e3 * rms[0, 0]:.2f} mm y {1e3 * rms[0, 1]:.2f} mm "
              f"angle {rms[0, 2]:.4f} rad | start v {vel0[0, 0]:+.3f} w {vel0[0, 2]:+.3f} (-v/r {-vel0[0, 0] / case.scene.bodies[0].radius:+.3f})"
              f" end err x {1e3 * r[-1, 0, 0]:+.2f} mm")
