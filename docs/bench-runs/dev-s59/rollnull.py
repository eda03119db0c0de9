"""Residual RMS of the nominal simulation over 1 s windows starting every 0.25 s, recorded data against its clean
replicate (``voe.gap.synth.null_like``), split by whether the ball rolls on the floor through the window
(development only).  PYTHONPATH=<clone> python rollnull.py SEED"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.shooting import Shooter, Window
from voe.gap.synth import null_like

s = int(sys.argv[1])
case = make_case(np.random.default_rng(s), "none", 1e-3, 12, 3.0, noise_kind="white")
sigma = np.array([[1e-3, 1e-3, 1e-2]] * 2)
null = null_like(case.scene, case.episodes, sigma, np.random.default_rng(1), 1e-3)
r = case.scene.bodies[0].radius
for name, eps in (("data", case.episodes), ("null", null)):
    sh = Shooter(case.scene, eps, 1e-3)
    out = {True: [], False: []}
    for e, ep in enumerate(eps):
        for k0 in range(12, len(ep.t) - 100, 25):
            w = Window(e, k0, k0 + 100)
            rolls = bool(np.all(np.abs(ep.pose[k0:k0 + 101, 0, 1] - r) < 0.005))
            res = sh.residual(w, None, None)
            out[rolls].append(float(np.sqrt((res[:, 0, 0] ** 2).mean())))
    for rolls in (True, False):
        a = np.array(out[rolls]) * 1e3
        print(f"{name} rolling={rolls!s:5s} windows {a.size:3d} ball x rms median {np.median(a):.2f} mm, "
              f"90th {np.quantile(a, 0.9):.2f} mm, max {a.max():.2f} mm")
