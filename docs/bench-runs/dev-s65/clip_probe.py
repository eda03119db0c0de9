"""Per-window log RMSE ratios of round-2 fits over round 1's accepted model, and the round's gain under smaller
clips of each window's log ratio (session 65; development only). The search clips log SSE ratios at +-10
(``voe.gap.search.LOG_CLIP``), i.e. log RMSE ratios at +-5.

    [CROSS=1] PYTHONPATH=<clone> python clip_probe.py SEED TRUTH EPISODES DURATION R1 CAND[,CAND...] [FINDER_SEED] [SCAN]
SCAN: comma-separated values of round 1's (one-parameter) effect to evaluate alone.
"""
import os, sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.stages import GapConfig, prepare, _folded
from voe.gap.search import window_gain, accept

seed, truth, n_ep, dur, r1name, cands = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5], sys.argv[6].split(",")
fseed = int(sys.argv[7]) if len(sys.argv) > 7 else seed
scan = [float(v) for v in sys.argv[8].split(",")] if len(sys.argv) > 8 else []
case = make_case(np.random.default_rng(seed), truth, episodes=n_ep, duration=dur)
cfg = GapConfig(cross_fit=os.environ.get("CROSS") == "1")
p = prepare(case.scene, case.episodes, tuple(k for k in EFFECTS if k != "none"), cfg)
data = _folded(p, p.shooter, p.episodes, p.bad, cfg, fseed)
before = data.heldout_sse()
c = p.candidates
r1 = data.fit_candidate(None, c[r1name])
acc = accept(data, r1, window_gain(before, r1.window_sse), before)
b2 = acc.window_sse
CLIPS = (5.0, 2.0, 1.0, 0.5)


def show(label, before_sse, after_sse):
    lr = 0.5 * np.log(np.maximum(after_sse, 1e-300) / np.maximum(before_sse, 1e-300))  # (W,) log RMSE ratio
    g = {cl: 1 - np.exp(np.clip(lr, -cl, cl).mean()) for cl in CLIPS}
    big = np.sort(lr[np.abs(lr) > 0.3])
    print(f"  {label:34s} W={lr.size} gain@clip " + " ".join(f"{cl:g}:{100 * v:6.1f}%" for cl, v in g.items())
          + f" | |lr|>0.3: {np.round(big, 2).tolist()}", flush=True)


print(seed, truth, "cross" if cfg.cross_fit else "three-way", "round 1", r1name, [np.round(x, 4) for x in acc.fold_params])
show(f"{r1name} over nominal", before, b2)
for k in cands:
    r = data.fit_candidate(acc, c[k])
    show(f"+{k}", b2, r.window_sse)
for v in scan:
    show(f"{r1name} alone at {v:g}", b2, data.heldout_sse(acc.effect, tuple(np.array([v]) for _ in acc.fold_params)))
