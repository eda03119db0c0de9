"""Start-velocity error of every fitting/selection window of clean cases, by the ball's state at the
window start: is the ball's speed over- or under-estimated on average (development only)?

    PYTHONPATH=<clone> python vbias.py SEED0 N [white|coloured]
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.context import frame_labels
from voe.gap.finder import ALL_EFFECTS
from voe.gap.shooting import local_state
from voe.gap.stages import GapConfig, fit_windows, prepare

s0, n = int(sys.argv[1]), int(sys.argv[2])
kind = sys.argv[3] if len(sys.argv) > 3 else "white"
config = GapConfig(second_look=False)
rows = []  # (label, speed, along-error, since-impact samples)
for s in range(s0, s0 + n):
    case = make_case(np.random.default_rng(s), "none", 1e-3, 12, 3.0, noise_kind=kind)
    if case.scene.joints:
        continue
    clean = make_case(np.random.default_rng(s), "none", 0.0, 12, 3.0, noise_kind=kind)
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
    ids = tuple(i for i in range(len(p.episodes)) if i not in p.split.test)
    for w in fit_windows(p, ids, config):
        _, v_est, _ = p.shooter.initial(w.ep, w.k0)
        _, v_true, _ = local_state(clean.episodes[w.ep], w.k0, 2)
        lab = frame_labels(case.scene, clean.episodes[w.ep])[:, 0]
        imp = np.flatnonzero(lab[: w.k0] == "impact")
        since = w.k0 - imp[-1] if imp.size else 999
        sp = float(np.hypot(*v_true[0, :2]))
        along = float(np.dot(v_est[0, :2] - v_true[0, :2], v_true[0, :2]) / max(sp, 1e-9))
        rows.append((lab[w.k0], sp, along, since, s, p.half))
    print(s, "half", p.half, len(rows), flush=True)
labs = sorted({r[0] for r in rows})
for L in labs:
    a = np.array([r[2] for r in rows if r[0] == L and r[1] > 0.05])
    if a.size:
        print(f"{L:8s} n {a.size:4d} speed error along motion: mean {1e3 * a.mean():+.2f} mm/s, se {1e3 * a.std() / np.sqrt(a.size):.2f}, "
              f"median {1e3 * np.median(a):+.2f}, share > 0 {np.mean(a > 0):.2f}")
for lo, hi in ((0, 30), (30, 60), (60, 120), (120, 999), (999, 1000)):
    a = np.array([r[2] for r in rows if r[0] == "rolling" and r[1] > 0.05 and lo <= r[3] < hi])
    if a.size:
        print(f"rolling, {lo}-{hi} samples after an impact: n {a.size} mean {1e3 * a.mean():+.2f} mm/s se {1e3 * a.std() / np.sqrt(a.size):.2f} share > 0 {np.mean(a > 0):.2f}")
