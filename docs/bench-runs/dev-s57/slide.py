"""Feasibility: a box's sliding deceleration against x, floor patches vs controls."""
import json
import sys

import numpy as np
from scipy.signal import savgol_filter

from voe.gap.bench import make_case, plan
from voe.gap.context import frame_labels, near_bodies

HALF = 12


def slide_units(case, eps):
    out = []  # (episode, body, x, decel, v)
    for i, ep in enumerate(eps):
        lab = frame_labels(case.scene, ep)
        near = near_bodies(case.scene, ep)
        dt = float(np.median(np.diff(ep.t)))
        kw = {"window_length": 2 * HALF + 1, "polyorder": 3, "axis": 0, "delta": dt, "mode": "interp"}
        pos = savgol_filter(ep.pose, deriv=0, **kw)
        vel = savgol_filter(ep.pose, deriv=1, **kw)
        acc = savgol_filter(ep.pose, deriv=2, **kw)
        for b, spec in enumerate(case.scene.bodies):
            sl = ((lab[:, b] == "sliding") & ~near[:, b]).astype(float)
            ok = np.convolve(sl, np.ones(2 * HALF + 1), mode="same") >= 2 * HALF + 1
            ok[:HALF] = ok[len(ok) - HALF:] = False
            ok &= np.abs(vel[:, b, 0]) > 0.05
            for k in np.flatnonzero(ok):
                out.append((i, b, pos[k, b, 0], -acc[k, b, 0] * np.sign(vel[k, b, 0]), vel[k, b, 0]))
    return np.array(out) if out else np.zeros((0, 5))


def main(which, seeds):
    for sb in seeds:
        for s, truth, _nk, role in plan(130, sb, compound=8, outside=12, clean=0):
            if which == "patch" and truth != "floor_patch":
                continue
            if which == "ctl" and truth not in ("none", "friction", "mass", "restitution", "rolling_resistance"):
                continue
            case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind="white")
            if case.scene.joints:
                continue
            u = slide_units(case, case.episodes[:6])
            rec = {"seed": s, "truth": truth, "n": len(u), "true": {k: [float(x) for x in v[0]] for k, v in case.true.items()},
                   "bodies": [b.shape for b in case.scene.bodies]}
            if len(u):
                rec["bodies_sliding"] = {int(b): int((u[:, 1] == b).sum()) for b in np.unique(u[:, 1])}
                rec["x"] = [round(float(u[:, 2].min()), 2), round(float(u[:, 2].max()), 2)]
                bins = np.floor(u[:, 2] / 0.25)
                rec["bins"] = {int(k): [int((bins == k).sum()), round(float(np.median(u[bins == k, 3])), 2)]
                               for k in np.unique(bins)}
            print(json.dumps(rec), flush=True)


if __name__ == "__main__":
    main(sys.argv[1], [int(v) for v in sys.argv[2:]])
