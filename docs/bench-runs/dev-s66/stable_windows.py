"""Round 2 on stable windows only (session 66 probe; development only).

Round 1's winner fitted and accepted as the search does, its 95 % interval on the fitting episodes; the round-1 model
alone evaluated at points across that interval (each part at its ends and between, the others at the estimate), per
selection window. A window is *unstable* when some point inside the interval moves its selection SSE by more than
a log ratio TAU from the estimate's: its outcome flips within what round 1 already allows (collision windows).
Then round-2 candidates on top, each member's gain over round 1 on all windows and on the stable ones, next to the
best gain the round-1 model alone reaches at a point of its interval (the "re-spotting" allowance) on the same sets.

    [CROSS=1] PYTHONPATH=<clone> python stable_windows.py SEED TRUTH EPISODES DURATION R1 CAND[,CAND...] [FINDER_SEED]
"""
import os
import sys
import time

import numpy as np

from voe.gap.bench import make_case
from voe.gap.check import model_intervals
from voe.gap.effects import EFFECTS
from voe.gap.search import accept, window_gain
from voe.gap.stages import GapConfig, _folded, fit_context, prepare

seed, truth, n_ep, dur, r1name = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
cands = sys.argv[6].split(",")
fseed = int(sys.argv[7]) if len(sys.argv) > 7 else seed
t0 = time.process_time()
case = make_case(np.random.default_rng(seed), truth, episodes=n_ep, duration=dur)
cfg = GapConfig(cross_fit=os.environ.get("CROSS") == "1")
p = prepare(case.scene, case.episodes, tuple(k for k in EFFECTS if k != "none"), cfg)
data = _folded(p, p.shooter, p.episodes, p.bad, cfg, fseed)
before = data.heldout_sse()
c = p.candidates
r1 = data.fit_candidate(None, c[r1name])
acc = accept(data, r1, window_gain(before, r1.window_sse), before)
s0 = acc.window_sse  # (W,)
lo, hi = model_intervals(p, p.split.fit, acc, fit_context(p), cfg, 0)
print(seed, truth, "round1", r1name, [np.round(x, 4) for x in acc.fold_params], f"gain {window_gain(before, s0):.4f}",
      "interval", np.round(lo, 4), np.round(hi, 4), f"W={s0.size}", flush=True)
pts = []  # fold parameter tuples across the interval
for j in range(len(acc.params)):
    for v in np.linspace(lo[j], hi[j], 7):
        pts.append(tuple(np.where(np.arange(len(x)) == j, v, x) for x in acc.fold_params))
S = np.stack([data.heldout_sse(acc.effect, fp) for fp in pts])  # (K, W)
lr = np.abs(np.log(np.maximum(S, 1e-300) / np.maximum(s0, 1e-300)))  # (K, W)
u = lr.max(axis=0)  # (W,)
print("  per-window max |log SSE ratio| across the interval: quantiles 50/75/90/100 %",
      np.round(np.quantile(u, [0.5, 0.75, 0.9, 1.0]), 3), f"cpu {time.process_time() - t0:.0f}", flush=True)
fits = {k: data.fit_candidate(acc, c[k]) for k in cands}
for tau in (np.inf, 1.0, 0.5, 0.25):
    m = u <= tau
    jit = max(window_gain(s0[m], S[i][m]) for i in range(len(S)))
    row = ", ".join(f"{k} {window_gain(s0[m], r.window_sse[m]):+.4f}" for k, r in fits.items())
    print(f"  tau {tau}: {m.sum()}/{m.size} windows; round 1 re-spotted best {jit:+.4f}; members {row}", flush=True)
for k, r in fits.items():
    print(f"  {k}: joint {[np.round(x, 4) for x in r.fold_params]}", flush=True)
print(f"cpu {time.process_time() - t0:.0f}")
