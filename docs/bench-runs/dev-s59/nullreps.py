"""A candidate's round-1 gain on R clean replicates of a case (each ``null_like`` with its own noise draw, fitted
as the null fits it), against the data's gain and the one replicate the finder draws (development only).

    PYTHONPATH=<clone> python nullreps.py SEED TRUTH NOISE_KIND CANDIDATE R
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.search import window_gain
from voe.gap.shooting import Shooter
from voe.gap.stages import GapConfig, _bad_starts, _folded, prepare
from voe.gap.synth import null_like

s, truth, kind, cand, reps = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5])
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
config = GapConfig(second_look=False)
p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
gains = []
data = _folded(p, p.shooter, p.episodes, p.bad, config, s)
res = data.fit_candidate(None, p.candidates[cand])
print(f"{s} data: {cand} {np.round(res.params, 5).tolist()} gain {window_gain(data.heldout_sse(), res.window_sse):.4f}")
for i in range(reps):
    eps = null_like(p.scene, p.episodes, p.sigma, np.random.default_rng(10_000 + i), p.substep, p.phi, p.jitter)
    fo = _folded(p, Shooter(p.scene, eps, p.substep, p.half), eps, _bad_starts(p.scene, eps, p.half), config, s)
    r = fo.fit_candidate(None, p.candidates[cand])
    g = window_gain(fo.heldout_sse(), r.window_sse)
    gains.append(g)
    print(f"  replicate {i}: {np.round(r.params, 5).tolist()} gain {g:.4f}", flush=True)
g = np.array(gains)
print(f"  replicates: gain > 0.05 in {int((g > 0.05).sum())}/{g.size}, at 0 in {int((g == 0).sum())}, "
      f"median {np.median(g):.4f}, max {g.max():.4f}")
