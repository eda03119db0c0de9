"""Round 2 by hand on one case (session 65): round 1's winner fitted and accepted as the search does, its 95 %
interval on the fitting episodes, then round-2 candidates on top; for each, where its joint fit moved the round-1
part, whether that lies inside round 1's interval, and what the round-1 model alone gains there (the part of the
member's gain that is only the round-1 part moving). Development only.

    [CROSS=1] PYTHONPATH=<clone> python jitter_allow.py SEED TRUTH EPISODES DURATION R1 CAND[,CAND...] [FINDER_SEED]
"""
import sys, time
import numpy as np
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.stages import GapConfig, prepare, _folded, fit_context
from voe.gap.search import window_gain, accept
from voe.gap.check import model_intervals

seed, truth, n_ep, dur, r1name, cands = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5], sys.argv[6].split(",")
t0 = time.process_time()
case = make_case(np.random.default_rng(seed), truth, episodes=n_ep, duration=dur)
import os
cfg = GapConfig(cross_fit=os.environ.get("CROSS") == "1")  # CROSS=1: the second look's split
p = prepare(case.scene, case.episodes, tuple(k for k in EFFECTS if k != "none"), cfg)
fseed = int(sys.argv[7]) if len(sys.argv) > 7 else seed  # the finder draws its windows from its own seed (the bench: the case seed)
data = _folded(p, p.shooter, p.episodes, p.bad, cfg, fseed)
before = data.heldout_sse()
c = p.candidates
r1 = data.fit_candidate(None, c[r1name]); g1 = window_gain(before, r1.window_sse)
acc = accept(data, r1, g1, before)
print(seed, truth, "round1", r1name, [np.round(x, 4) for x in acc.fold_params], f"gain {window_gain(before, acc.window_sse):.4f}", flush=True)
lo, hi = model_intervals(p, p.split.fit, acc, fit_context(p), cfg, 0)
print("  round-1 interval", np.round(lo, 4), np.round(hi, 4), f"cpu {time.process_time() - t0:.0f}", flush=True)
b2 = acc.window_sse
n1 = len(acc.params)
for k in cands:
    r = data.fit_candidate(acc, c[k])
    g = window_gain(b2, r.window_sse)
    d = [x[:n1] for x in r.fold_params]
    inside = all(np.all((x >= lo) & (x <= hi)) for x in d)
    alone = data.heldout_sse(acc.effect, tuple(d))
    ga = window_gain(b2, alone)
    print(f"  {k}: joint {[np.round(x, 4) for x in r.fold_params]} gain {g:.4f}; round-1 part moved to "
          f"{[np.round(x, 4) for x in d]} ({'inside' if inside else 'OUTSIDE'} round 1's interval), round-1 model alone "
          f"there gains {ga:.4f}, the member over that {window_gain(alone, r.window_sse):.4f}  cpu {time.process_time() - t0:.0f}", flush=True)
