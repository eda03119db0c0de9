"""One case's test windows, frame by frame, where the truth's own parameters leave a window worse than the nominal
model (development only): data, nominal and truth poses, residuals in sigmas, and the frame labels.

    PYTHONPATH=<clone>:../dev-s62 python window_probe.py SEED TRUTH NOISE_KIND [WINDOW ...]
"""
import sys

import numpy as np
from startfit import truth_pairs

from voe.gap.context import frame_labels

seed, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
only = {int(a) for a in sys.argv[4:]}
case, p, model, pairs = truth_pairs(seed, truth, kind)
sh = p.shooter
print("truth", case.true, "bodies", case.scene.names, "split test", p.split.test, "substep", p.substep, "half", p.half)
for i, (w, params) in enumerate(pairs):
    res_n = sh.residuals([w], None, None)[0]  # (n, B, 3)
    res_t = sh.residuals([w], model.effect, params)[0]
    sp = sh.sigma_pred(w, p.sigma)
    zn = np.sqrt(np.mean((res_n / sp)[1:] ** 2, axis=0))  # (B, 3)
    zt = np.sqrt(np.mean((res_t / sp)[1:] ** 2, axis=0))
    print(f"window {i}: ep {w.ep} k {w.k0}..{w.k1}; z nominal {np.round(zn, 1).tolist()} truth {np.round(zt, 1).tolist()}")
    if only and i not in only:
        continue
    ep = sh.episodes[w.ep]
    lab = frame_labels(p.scene, ep)
    sim_n = sh.simulate(w, None, None)
    sim_t = sh.simulate(w, model.effect, params)
    for j, k in enumerate(range(w.k0, w.k1 + 1)):
        if j % 5 and j < len(res_n) - 1:
            continue
        row = [f"t {ep.t[k]:.2f}"]
        for b, name in enumerate(p.scene.names):
            row.append(f"{name}[{lab[k, b]}] data ({ep.pose[k, b, 0]:+.4f},{ep.pose[k, b, 1]:+.4f},{ep.pose[k, b, 2]:+.3f})"
                       f" nom-data ({1e3 * res_n[j, b, 0]:+.1f},{1e3 * res_n[j, b, 1]:+.1f}mm,{res_n[j, b, 2]:+.3f})"
                       f" tru-data ({1e3 * res_t[j, b, 0]:+.1f},{1e3 * res_t[j, b, 1]:+.1f}mm,{res_t[j, b, 2]:+.3f})")
        print("  " + " | ".join(row))
