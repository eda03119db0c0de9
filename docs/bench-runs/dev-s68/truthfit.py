"""Development probe: on one bench case, the selection-window RMSE of the nominal model, of the hidden truth
at its true parameters, and of round 1's fit of each named candidate (the finder's own data folds and windows).

    PYTHONPATH=<clone> python truthfit.py SEED TRUTH NOISE_KIND CAND[,CAND...]

Why: a compound miss (constant_acceleration + angular_damping named spring_anchor + angular_damping, 5905132 and
9404136) can come from the search (the truth fits better but was not found) or from the data (the truth does not
fit the selection windows better). This tells the two apart at a few fits' cost, without the whole finder.
"""
import sys
import time

import numpy as np

from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.finder import ALL_EFFECTS
from voe.gap.search import window_gain
from voe.gap.stages import GapConfig, _folded, prepare

s, truth, kind, cands = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4].split(",")
t0 = time.time()
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
print(s, truth, kind, "true:", {k: (np.round(p, 4).tolist(), b) for k, (p, b) in case.true.items()})
cfg = GapConfig()
p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
data = _folded(p, p.shooter, p.episodes, p.bad, cfg, s)
n = len(data.test)


def rmse(sse: np.ndarray) -> float:
    return float(np.sqrt(np.sum(sse) / max(sum(f._n_test for f in data.folds), 1)))


print(f"split {p.split.scheme}, {len(data.folds)} folds, {n} selection windows")
nominal = data.heldout_sse()
print(f"nominal: selection RMSE {rmse(nominal):.5f}")
parts = [EFFECTS.get(k)(bodies=b) for k, (_, b) in case.true.items()]
eff = parts[0] if len(parts) == 1 else EffectSum(tuple(parts))
tp = np.concatenate([pp for pp, _ in case.true.values()])
print(f"truth at true parameters: selection RMSE {rmse(data.heldout_sse(eff, tuple(tp for _ in data.folds))):.5f}")
for c in cands:
    sub = [EFFECTS.get(k)() for k in c.split("+")]
    cur = None
    for e in sub:
        cur = data.fit_candidate(cur, e)
    ref = data.refine(cur)
    for tag, r in (("fit", cur), ("refined", ref)):
        print(f"{tag} {c}: selection RMSE {r.heldout_rmse:.5f}, window gain over nominal "
              f"{window_gain(nominal, r.window_sse):.3f}, params {np.round(r.params, 4).tolist()} ({time.time() - t0:.0f} s)")
