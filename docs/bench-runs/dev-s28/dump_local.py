"""Development (session 28): window-local clean replicates for the departure tail test.

Main's replicates are whole episodes simulated from each episode's estimated initial state: in a
chaotic arena their motion leaves the data's within a second or two, so a data window with a
collision its replicates do not have stands out (more replicates, more false alarms: dump20.py).
Here each window is cut out and its start state fitted one-sided from its own samples, for the
data and the replicates alike; a replicate is the nominal motion from the data window's fitted start
plus fresh noise of the data's noise model, so data and replicate follow the same path through the
window. (A first try started the replicate at the first sample of the data's centred start fit:
where that sample was near a contact every replicate departed, z ~ 120 against the data's 0.9.) Writes dep_local/<seed>.npz: data z (centred and one-sided start fits) and R
window-local replicate z on the 1-s windows, the episode replicate's 1-s z (the
signed-rank part) and the located count. Usage: dump_local.py OUT SEED:TRUTH:NOISEKIND ..."""
import sys, json, time, numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare
from voe.gap.finder import GapFinder
from voe.gap import departure as D
from voe.gap.locate import window_z, locate
from voe.gap.shooting import Shooter, make_windows, Window, ORDER
from voe.gap.synth import null_like, pose_noise
from voe.gap.recordings import Episode
R = 20


def local_replicates(sh, windows, sigma, phi, rng, n):
    """Data z (W,) and n window-local clean replicates' z (n, W).

    Each window is cut out with the samples its centred start fit uses before it (from ``lo``), so
    the data's z is the location's. A replicate starts at ``lo`` from the data's one-sided fitted
    state there, perturbed by a draw of that fit's own error (the fit repeated on the nominal motion
    plus fresh noise), runs the nominal model to the window's end, and gets fresh noise of the
    data's noise model; its z is the data's statistic (centred start fit at the window's start).
    The perturbation gives each replicate its own path, as the data's true start differs from the
    fitted one: replicates sharing one path all miss (or all have) a grazing collision the data has."""
    nfit = max(2 * sh.half + 1, ORDER + 3)
    seg, wins = [], []
    for i, w in enumerate(windows):
        ep = sh.episodes[w.ep]
        lo = min(max(0, w.k0 - nfit // 2), len(ep.t) - nfit, w.k0)
        seg.append(Episode(ep.id, ep.t[lo:w.k1 + 1].copy(), ep.pose[lo:w.k1 + 1].copy()))
        wins.append(Window(i, w.k0 - lo, w.k1 - lo))
    whole = [Window(i, 0, len(e.t) - 1) for i, e in enumerate(seg)]
    data = Shooter(sh.scene, seg, sh.substep, sh.half)
    zd = window_z(data, wins, sigma).max(axis=(1, 2))  # (W,) the location's window z
    base = data.simulate_many(whole, None, None)  # (n_i, B, 3): nominal from the data's fitted state at lo
    out = []
    for _ in range(n):
        drawn = Shooter(sh.scene, [Episode(e.id, e.t, m + pose_noise(m.shape, sigma, phi, rng)) for e, m in zip(seg, base)],
                        sh.substep, sh.half)
        path = drawn.simulate_many(whole, None, None)  # from the refitted (perturbed) start
        eps = [Episode(e.id, e.t, m + pose_noise(m.shape, sigma, phi, rng)) for e, m in zip(seg, path)]
        out.append(window_z(Shooter(sh.scene, eps, sh.substep, sh.half), wins, sigma).max(axis=(1, 2)))
    return zd, np.array(out).reshape(n, len(windows))


if __name__ == '__main__':
    out = sys.argv[1]
    for spec in sys.argv[2:]:
        t0 = time.time()
        seed, truth, nk = spec.split(':'); seed = int(seed)
        case = make_case(np.random.default_rng(seed), truth, noise_kind=nk)
        cfg = GapConfig()
        p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, cfg)
        rng = np.random.default_rng(seed)
        windows = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
        null_eps = null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi)
        z_null = window_z(Shooter(p.scene, null_eps, p.substep, p.half), windows, p.sigma).max(axis=(1, 2))
        z_thr = float(max(cfg.z_min, np.quantile(z_null, 0.95)))
        z = window_z(p.shooter, windows, p.sigma)
        located = locate(p.shooter, windows, z, z_thr)
        dep = make_windows(p.episodes, list(range(len(p.episodes))), D.WINDOW, bad_start=p.bad)
        zd05 = window_z(p.shooter, dep, p.sigma).max(axis=(1, 2))
        zs1, zl1 = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, R)
        np.savez(f'/work/eval/s28/dep_local/{seed}.npz', zd1=z.max(axis=(1, 2)), zn1=z_null, zl1=zl1, zd05=zd05, zs1=zs1,
                 located=len(located))
        r = dict(seed=seed, truth=truth, nk=nk, located=len(located), sec=round(time.time() - t0, 1))
        with open(out, 'a') as fh: fh.write(json.dumps(r) + '\n')
        print(json.dumps(r), flush=True)
