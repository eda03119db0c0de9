"""Per selection window of round 1: the winner's RMSE ratio (after/before), the window's start time and the
contact state of the ball at its start (development only).

    PYTHONPATH=<clone> python wingains.py SEED TRUTH NOISE_KIND
"""
import sys

import numpy as np

from voe.gap.bench import ball_box_gap, make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
config = GapConfig(second_look=False)
f = GapFinder(max_effects=3, seed=s, config=config).fit(case.scene, case.episodes)
r0 = f.search_.result.rounds[0]
win = r0.winner or max(r0.gains, key=r0.gains.get)
fitter = f.search_.fitter
wins = fitter.test
before = fitter.heldout_sse()
after = r0.results[win].window_sse
print(s, truth, kind, "round-1 winner", win, "gain", round(r0.gains[win], 4), "params", r0.results[win].params)
ratios = np.sqrt(after / before)
for w, b, a, q in zip(wins, before, after, ratios, strict=True):
    ep = f.episodes_[w.ep]
    pose = ep.pose[w.k0:w.k1 + 1]
    gap = ball_box_gap(f.scene_, pose)
    vx = np.gradient(pose[:, 0, 0], ep.t[w.k0:w.k1 + 1])
    print(f"  ep {ep.id:2d} t {ep.t[w.k0]:.2f}-{ep.t[w.k1]:.2f} rmse {np.sqrt(b / (w.k1 - w.k0 + 1)):.5f} "
          f"ratio {q:.3f} ball y {pose[0, 0, 1]:.3f} min gap to box {gap.min():.3f} "
          f"ball vx {vx[:5].mean():+.2f}->{vx[-5:].mean():+.2f} box dx {pose[-1, 1, 0] - pose[0, 1, 0]:+.4f}")
print("geometric-mean gain", 1 - np.exp(np.log(ratios).mean()))
