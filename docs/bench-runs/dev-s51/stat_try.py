"""Departure statistics tried offline on dump_z.py's window z-scores (development seeds only).

current: voe.gap.departure.departure_p (signed-rank and tail_p, Bonferroni).
stud:    the signed-rank test and a tail test whose per-window excess is divided by the spread (std of
         log z) of the column's other values, floored at FLOOR: a chaotic column, whose clean values
         spread widely, weighs less (a valid randomisation test: any statistic computed the same way
         for whichever row plays the data).
"""
import json
import sys

import numpy as np

from voe.gap.departure import N_PERM, _signed_rank_p, departure_p

FLOOR = float(sys.argv[2]) if len(sys.argv) > 2 else 0.25


def stud_tail_p(z_data, z_null, n_perm=N_PERM, seed=0, floor=FLOOR):
    zd = np.nan_to_num(np.asarray(z_data, dtype=float), nan=0.0, posinf=1e300)
    zn = np.nan_to_num(np.atleast_2d(np.asarray(z_null, dtype=float)), nan=0.0, posinf=1e300)
    if len(zd) < 3:
        return 1.0
    v = np.log(np.maximum(np.vstack([zd[None], zn]), 1e-6))  # (R + 1, W)
    n_rows, w = v.shape
    s1, s2 = v.sum(axis=0), (v ** 2).sum(axis=0)  # column sums for leave-one-out spread
    order = np.sort(v, axis=0)
    top1, top2 = order[-1], order[-2]

    def stat(chosen):  # (N, W)
        rest = np.where(chosen >= top1[None], top2[None], top1[None])
        m = n_rows - 1
        mean = (s1[None] - chosen) / m
        var = np.maximum((s2[None] - chosen ** 2) / m - mean ** 2, 0.0) * m / (m - 1)
        return np.sum(np.maximum(0.0, chosen - rest) / np.maximum(np.sqrt(var), floor), axis=1)

    t_obs = float(stat(v[:1])[0])
    if t_obs <= 0.0:
        return 1.0
    pick = np.random.default_rng(seed).integers(0, n_rows, size=(n_perm, w))
    t = stat(v[pick, np.arange(w)[None]])
    return float((1 + np.sum(t >= t_obs * (1 - 1e-12))) / (n_perm + 1))


d = np.load(sys.argv[1], allow_pickle=False)
meta = json.loads(str(d["meta"]))
rows = []
for s, (dp, truth, nk, verdict) in meta.items():
    z, zn, local = d[f"{s}_z"], d[f"{s}_zn"], d[f"{s}_local"]
    cur = departure_p(z, zn, local)
    new = min(1.0, 2.0 * min(_signed_rank_p(z, zn), stud_tail_p(z, local)))
    rows.append((s, truth, nk, verdict, cur, new))
    if truth != "none" or new < 0.05 or cur < 0.05:
        print(f"{s} {truth:12s} {nk:9s} {verdict:12s} current {cur:.4f} studentized {new:.4f}")
for truth in ("none", "floor_patch", "gust"):
    sel = [r for r in rows if r[1] == truth]
    print(f"{truth}: {len(sel)} cases; p < 0.01: current {sum(r[4] < 0.01 for r in sel)}, studentized "
          f"{sum(r[5] < 0.01 for r in sel)}; p < 0.05: current {sum(r[4] < 0.05 for r in sel)}, studentized {sum(r[5] < 0.05 for r in sel)}")
