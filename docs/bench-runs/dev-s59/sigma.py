"""The bench's noise sigma against the finder's estimate (development only).  PYTHONPATH=<clone> python sigma.py SEED"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.stages import GapConfig, prepare

s = int(sys.argv[1])
case = make_case(np.random.default_rng(s), "none", 1e-3, 12, 3.0, noise_kind="white")
p = prepare(case.scene, case.episodes, ALL_EFFECTS, GapConfig())
print(s, "estimated sigma (ball, box) x y angle:", np.round(p.sigma, 5).tolist(), "phi", np.round(p.phi, 3).tolist())
print("  ball radius", case.scene.bodies[0].radius, "true sigma fields:", [k for k in vars(case) if "sig" in k])
res = [ep.pose[1:-1] - 0.5 * (ep.pose[2:] + ep.pose[:-2]) for ep in case.episodes]
print("  second-difference rms / sqrt(1.5):", np.round(np.sqrt(np.mean(np.concatenate(res) ** 2, axis=0) / 1.5), 5).tolist())
