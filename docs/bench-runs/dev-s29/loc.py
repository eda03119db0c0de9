"""Development (session 29): the location stage on main's code (departure p, located, jitter)."""
import sys, json, time, numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, locate_step
from voe.gap.finder import GapFinder
out = sys.argv[1]
for spec in sys.argv[2:]:
    seed, truth, nk = spec.split(':'); seed = int(seed)
    t0 = time.process_time()
    case = make_case(np.random.default_rng(seed), truth, noise_kind=nk)
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, cfg)
    loc = locate_step(p, cfg, np.random.default_rng(seed))
    r = dict(seed=seed, truth=truth, nk=nk, located=len(loc.located), p=loc.departure_p,
             jitter_ms=None if getattr(p, "jitter", None) is None else round(p.jitter.seconds * 1e3, 3), cpu=round(time.process_time() - t0, 1))
    with open(out, 'a') as fh: fh.write(json.dumps(r) + '\n')
    print(json.dumps(r), flush=True)
