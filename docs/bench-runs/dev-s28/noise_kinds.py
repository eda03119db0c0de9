"""Development (session 28): clean cases with timestamp jitter and dropouts, which the null's noise
model does not reproduce. Main's departure p (its own location stage) and the window-local tail
(dump_local.local_replicates, R = 10) with main's signed-rank part. Usage: noise_kinds.py OUT SEED:none:KIND ..."""
import sys, json, numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, locate_parts
from voe.gap.finder import GapFinder
from voe.gap.departure import _signed_rank_p, tail_p
from voe.gap.locate import window_z
from voe.gap.shooting import Shooter
from dump_local import local_replicates
out = sys.argv[1]
for spec in sys.argv[2:]:
    seed, truth, nk = spec.split(':'); seed = int(seed)
    case = make_case(np.random.default_rng(seed), truth, noise_kind=nk)
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, cfg)
    rng = np.random.default_rng(seed)
    null_eps, finish = locate_parts(p, cfg, rng)
    loc = finish()
    zd = window_z(p.shooter, loc.windows, p.sigma).max(axis=(1, 2))
    zn = window_z(Shooter(p.scene, null_eps, p.substep, p.half), loc.windows, p.sigma).max(axis=(1, 2))
    _, zl = local_replicates(p.shooter, loc.windows, p.sigma, p.phi, rng, 10)
    sr, tl = _signed_rank_p(zd, zn), tail_p(zd, zl)
    r = dict(seed=seed, truth=truth, nk=nk, located=len(loc.located), p_main=loc.departure_p, sr=sr, tail_local=tl,
             p_new=min(1.0, 2 * min(sr, tl)))
    with open(out, 'a') as fh: fh.write(json.dumps(r) + '\n')
    print(json.dumps(r), flush=True)
