"""Is a round-2 member a stand-in? (session 66 probe; development only.)

Round 1's winner fitted and accepted as the search does; each round-2 candidate fitted on top. For each member, its
own part set back to its nominal values (NaN entries, e.g. positions, kept as fitted), the earlier parts left where
the joint fit put them: per selection window, the RMS change of the prediction in noise sigmas (median sigma of the
position channels), as ``voe.gap.verify.Verification.moved`` measures a law's expression on test windows. A member
whose own part moves no selection window past EXPRESSED_Z only re-spots the earlier parts.

    [CROSS=1] PYTHONPATH=<clone> python stand_in.py SEED TRUTH EPISODES DURATION R1 CAND[,CAND...]|all [FINDER_SEED]
"""
import os
import sys
import time

import numpy as np

from voe.gap.bench import make_case
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
ctx = fit_context(p)
noise = float(np.median(p.sigma[:, :2]))
before = data.heldout_sse()
c = p.candidates
if cands == ["all"]:
    cands = [k for k in c if k != r1name]
r1 = data.fit_candidate(None, c[r1name])
acc = accept(data, r1, window_gain(before, r1.window_sse), before)
print(seed, truth, "round1", r1name, [np.round(x, 4) for x in acc.fold_params],
      f"gain {window_gain(before, acc.window_sse):.4f}", flush=True)
for k in cands:
    r = data.fit_candidate(acc, c[k])
    nom = c[k].nominal(ctx)  # (Q,)
    q = len(nom)
    back = tuple(np.concatenate([x[:-q], np.where(np.isfinite(nom), nom, x[-q:])]) for x in r.fold_params)
    a = data.residuals(r.effect, r.fold_params)
    b = data.residuals(r.effect, back)
    moved = np.array([np.sqrt(np.mean((x - y) ** 2)) for x, y in zip(a, b, strict=True)]) / noise  # (W,)
    own = window_gain(data.heldout_sse(r.effect, back), r.window_sse)
    print(f"  {k}: gain {window_gain(acc.window_sse, r.window_sse):+.4f}, own part {[np.round(x[-q:], 4) for x in r.fold_params]}"
          f" (nominal {np.round(nom, 4)}), by itself {own:+.4f}; windows moved (sigmas): max {moved.max():.2f}, "
          f"n > 3: {(moved > 3).sum()}/{moved.size}, median {np.median(moved):.2f}", flush=True)
print(f"cpu {time.process_time() - t0:.0f}")
