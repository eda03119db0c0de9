"""One case's flight units for a library effect (one line per episode and 0.25 s slot: samples, median residual,
times), and fdrift2's variants on them.

usage: python units67.py SEED TRUTH P0,P1[,..] [EPISODES]   (e.g. 9260067 constant_acceleration -0.041,0.298)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fdrift2 as F
from voe.gap import drift_flight as D
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.prefit import flight_samples, seen_missing
from voe.gap.stages import context_for
seed, truth = int(sys.argv[1]), sys.argv[2]
p0 = np.array([float(v) for v in sys.argv[3].split(",")])
episodes = [int(v) for v in sys.argv[4].split(",")] if len(sys.argv) > 4 else list(range(6))
case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind="white")
eps = [case.episodes[i] for i in episodes]
seen = flight_samples(case.scene, eps, around=True)
ctx = context_for(case.scene, eps)
e = EFFECTS.get(truth)()
p = D._flight_fit(seen, e, p0, case.scene, ctx)
print("flight fit", p, "true", case.true)
res = seen.dacc - seen_missing(e, p, seen, case.scene)[0]
slot = np.floor(seen.time / D.FLIGHT_SLOT).astype(int)
for key in sorted(set(zip(seen.episode.tolist(), slot.tolist(), strict=True))):
    m = (seen.episode == key[0]) & (slot == key[1])
    print(key, int(m.sum()), np.round(np.median(res[m], axis=0), 3), "times", np.round(seen.time[m].min(), 2), np.round(seen.time[m].max(), 2))
tab = F.unit_table(seen, e, p0, case.scene, ctx)
print("floor", tab[2], {k: F.test(tab, v) for k, v in F.VARIANTS.items()})
print("landed", D.flight_drift(seen, e, p0, case.scene, ctx))
