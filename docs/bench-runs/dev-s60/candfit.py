"""Round-1 fits of named candidates on a bench case's data, as the three-way search fits them: parameters
and selection gain (development only).

    PYTHONPATH=<clone> python candfit.py SEED TRUTH NOISE_KIND CANDIDATE [CANDIDATE ...]
"""
import sys
import time

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.search import window_gain
from voe.gap.stages import GapConfig, _folded, prepare

s, truth, kind, cands = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4:]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
config = GapConfig(second_look=False)
p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
data = _folded(p, p.shooter, p.episodes, p.bad, config, s)
print(s, truth, "true", case.true, "split", p.split.fit, p.split.select, flush=True)
for c in cands:
    t0 = time.time()
    res = data.fit_candidate(None, p.candidates[c])
    print(f"  {c}: {np.round(res.params, 4).tolist()} selection gain {window_gain(data.heldout_sse(), res.window_sse):.4f} "
          f"({time.time() - t0:.0f} s)", flush=True)
