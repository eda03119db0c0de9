"""Development (session 28): the location stage with R = 20 clean replicates on the half-second and the 1-s windows
(main uses 4: the first replicate and REPLICATES - 1 = 3 more). The first 4 rows equal main's (same rng
stream: more_replicates draws its replicates in order). Writes dep/<seed>.npz and one JSON line per case.
Usage: dump20.py OUT SEED:TRUTH:NOISEKIND ..."""
import sys, json, time, numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare
from voe.gap.finder import GapFinder
from voe.gap import departure as D
from voe.gap.locate import window_z, locate
from voe.gap.shooting import Shooter, make_windows
from voe.gap.synth import null_like, nominal_motion, pose_noise
from voe.gap.recordings import Episode
R = 20
out = sys.argv[1]
for spec in sys.argv[2:]:
    t0 = time.time()
    seed, truth, nk = spec.split(':'); seed = int(seed)
    case = make_case(np.random.default_rng(seed), truth, noise_kind=nk)
    f = GapFinder(seed=seed)
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, f.effects, cfg)
    rng = np.random.default_rng(seed)
    # locate_parts' finish, with R - 1 more replicates instead of 3
    windows = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
    null_eps = null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi)
    null_shooter = Shooter(p.scene, null_eps, p.substep, p.half)
    z_null = window_z(null_shooter, windows, p.sigma).max(axis=(1, 2))
    z_thr = float(max(cfg.z_min, np.quantile(z_null, 0.95)))
    z = window_z(p.shooter, windows, p.sigma)
    located = locate(p.shooter, windows, z, z_thr)
    dep = make_windows(p.episodes, list(range(len(p.episodes))), D.WINDOW, bad_start=p.bad)
    # D.more_replicates with n = R - 1, computing each replicate's z on both window sets
    zero = np.zeros_like(p.sigma)
    motion = [m + pose_noise(m.shape, zero, 0.0, rng) for m in nominal_motion(p.scene, p.episodes, p.substep)]
    more, more1 = [], []
    for _ in range(R - 1):
        eps = [Episode(ep.id, ep.t.copy(), m + pose_noise(m.shape, p.sigma, p.phi, rng)) for ep, m in zip(p.episodes, motion)]
        sh = Shooter(p.scene, eps, p.substep, p.half)
        more.append(window_z(sh, dep, p.sigma).max(axis=(1, 2)))
        more1.append(window_z(sh, windows, p.sigma).max(axis=(1, 2)))
    more, more1 = np.array(more), np.array(more1)
    zd05 = window_z(p.shooter, dep, p.sigma).max(axis=(1, 2))
    zn05 = np.vstack([window_z(null_shooter, dep, p.sigma).max(axis=(1, 2))[None], more])  # (R, W')
    zd1 = z.max(axis=(1, 2))
    p_main = D.departure_p(zd1, z_null, (zd05, zn05[:4]))
    np.savez(f'/work/eval/s28/dep/{seed}.npz', zd1=zd1, zn1=np.vstack([z_null[None], more1]), zd05=zd05, zn05=zn05, located=len(located), p_main=p_main)
    r = dict(seed=seed, truth=truth, nk=nk, located=len(located), p_main=p_main, sec=round(time.time() - t0, 1))
    with open(out, 'a') as fh: fh.write(json.dumps(r) + '\n')
    print(json.dumps(r), flush=True)
