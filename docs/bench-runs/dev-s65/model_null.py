"""Prototype (session 65, development only): round 2's threshold from a replicate simulated under the data's
accepted round-1 model instead of the nominal scene.

The data: round 1's winner R1 fitted and accepted as the search does, then every other candidate on top (the
data's round-2 gains). The model null: a replicate of the episodes simulated under the accepted model (its
full-data parameters, each episode from its estimated start, the data's noise model), searched the same way:
R1 fitted and accepted, every other candidate on top, ``null_threshold`` over them. Printed beside the data's
gains, so one can read whether the re-spotting of R1 that carries round-2 gains on the data (the speed case:
docs/bench-runs/dev-s64/round_two.txt) is what a replicate of the model itself also shows.

    [CROSS=1] PYTHONPATH=<clone> python model_null.py SEED TRUTH EPISODES DURATION R1 [FINDER_SEED] [REPS]
"""
import os, sys, time
import numpy as np
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.stages import GapConfig, prepare, _folded, _bad_starts
from voe.gap.search import window_gain, accept, null_threshold, gain_lower_bound
from voe.gap.shooting import local_state, Shooter
from voe.gap.synth import simulate_episode

seed, truth, n_ep, dur, r1name = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
fseed = int(sys.argv[6]) if len(sys.argv) > 6 else seed
reps = int(sys.argv[7]) if len(sys.argv) > 7 else 1
t0 = time.process_time()
case = make_case(np.random.default_rng(seed), truth, episodes=n_ep, duration=dur)
cfg = GapConfig(cross_fit=os.environ.get("CROSS") == "1")
p = prepare(case.scene, case.episodes, tuple(k for k in EFFECTS if k != "none"), cfg)
c = p.candidates


def round_two(fitter, label):
    before = fitter.heldout_sse()
    r1 = fitter.fit_candidate(None, c[r1name])
    acc = accept(fitter, r1, window_gain(before, r1.window_sse), before)
    b2 = acc.window_sse
    res = {k: fitter.fit_candidate(acc, e) for k, e in c.items() if k != r1name}
    gains = {k: window_gain(b2, r.window_sse) for k, r in res.items()}
    thr = null_threshold(b2, res, cfg.null_alpha, fseed)[0]
    top = sorted(gains.items(), key=lambda kv: -kv[1])[:5]
    print(f"  {label}: round 1 {r1name} {[np.round(x, 4) for x in acc.fold_params]} gain "
          f"{window_gain(before, b2):.4f}; round 2 best " + ", ".join(f"{k} {g:.4f} (lb {gain_lower_bound(b2, res[k].window_sse):.4f})"
                                                                 for k, g in top)
          + f"; threshold from these {max(thr, cfg.min_gain):.4f} (raw {thr:.4f})  cpu {time.process_time() - t0:.0f}", flush=True)
    return acc


print(seed, truth, "cross" if cfg.cross_fit else "three-way", flush=True)
data = _folded(p, p.shooter, p.episodes, p.bad, cfg, fseed)
acc = round_two(data, "data")
rng = np.random.default_rng(seed + 1)
for i in range(reps):
    eps = []
    for ep in p.episodes:
        pose0, vel0, _ = local_state(ep, 0, None, p.substep)
        eps.append(simulate_episode(p.scene, ep.id, ep.t, pose0, vel0, acc.effect, acc.params, p.sigma, rng, p.substep, p.phi))
    sh = Shooter(p.scene, eps, p.substep, p.half)
    round_two(_folded(p, sh, eps, _bad_starts(p.scene, eps, p.half), cfg, fseed), f"model null {i}")
