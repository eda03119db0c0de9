"""Development (session 29): voe.gap.jitter.timing_jitter on bench cases (no simulation of the finder)."""
import sys, json, numpy as np
from voe.gap.bench import make_case
from voe.gap.shooting import noise_model
from voe.gap.jitter import timing_jitter
for spec in sys.argv[1:]:
    seed, truth, nk = spec.split(':')
    case = make_case(np.random.default_rng(int(seed)), truth, noise_kind=nk)
    j = timing_jitter(case.episodes, noise_model(case.episodes)[1])
    print(json.dumps(dict(seed=int(seed), truth=truth, nk=nk, jitter_ms=None if j is None else round(j.seconds * 1e3, 3))), flush=True)
