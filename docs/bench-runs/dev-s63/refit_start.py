"""Prototype (development only): a test window's z after its start velocity is refitted under the model asked,
a MAP estimate with the start fit's own error as the prior (``startfit.py``), beside the plain z, for the nominal
model and the truth. The question: does a start refit take away the departures that start noise and a collision
make (the truth's z falls to the noise), while a missing effect's stays (the nominal's z does not)?

    PYTHONPATH=<clone>:../dev-s62 python refit_start.py SEED TRUTH NOISE_KIND [WINDOW ...]
"""
import sys

import numpy as np
from startfit import refit, sigma_v, truth_pairs, z_of

seed, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
only = {int(a) for a in sys.argv[4:]}
case, p, model, pairs = truth_pairs(seed, truth, kind)
sh = p.shooter
dt = float(np.median(np.diff(sh.episodes[0].t)))
sv = sigma_v(sh.half, dt, p.sigma)
print(seed, truth, "half", sh.half, "start-velocity sigma (B,3)", np.round(sv, 4).tolist())
for i, (w, params) in enumerate(pairs):
    if only and i not in only:
        continue
    out = []
    for label, eff, prm in (("nominal", None, None), ("truth", model.effect, params)):
        plain = z_of(sh, w, sh.simulate(w, eff, prm), p.sigma)
        pred, dv = refit(sh, w, eff, prm, p.sigma, sv)
        out.append(f"{label} z {plain:.1f} -> refitted {z_of(sh, w, pred, p.sigma):.1f} (dv/sigma "
                   f"{np.round((dv / np.where(sv > 0, sv, 1)).reshape(-1), 1).tolist()})")
    print(f"window {i} ep {w.ep} k {w.k0}..{w.k1}: " + " | ".join(out), flush=True)
