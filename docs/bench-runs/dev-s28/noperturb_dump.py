"""Development (session 28): the window-local replicates without the start perturbation (every
replicate the nominal motion from the data's fitted state at lo, only the noise redrawn), R = 10,
drawn from the finder's rng after its clean replicate. Usage: noperturb_dump.py OUT SEED:TRUTH:KIND ..."""
import sys, json, numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare
from voe.gap.finder import GapFinder
from voe.gap.departure import tail_p
from voe.gap.locate import window_z
from voe.gap.shooting import make_windows
from voe.gap.synth import null_like
from variants import no_perturb
out = sys.argv[1]
for spec in sys.argv[2:]:
    seed, truth, nk = spec.split(':'); seed = int(seed)
    case = make_case(np.random.default_rng(seed), truth, noise_kind=nk)
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, cfg)
    rng = np.random.default_rng(seed)
    windows = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
    null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi)
    zd = window_z(p.shooter, windows, p.sigma).max(axis=(1, 2))
    zl = no_perturb(p.shooter, windows, p.sigma, p.phi, rng, 10)
    r = dict(seed=seed, truth=truth, nk=nk, tail_noperturb=tail_p(zd, zl), rank=float(np.mean(zl < zd[None])))
    with open(out, 'a') as fh: fh.write(json.dumps(r) + '\n')
    print(json.dumps(r), flush=True)
