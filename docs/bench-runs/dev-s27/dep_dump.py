"""Development (session 27): the location stage alone; the departure p as main computes it, and with a third
Bonferroni part: the tail test on the 1-s windows against the same R replicates (their 1-s window z).
Usage: dep_trace.py OUT SEED:TRUTH:NOISEKIND ...  (appends one JSON line per case)"""
import sys, json, numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, locate_parts
from voe.gap.finder import GapFinder
from voe.gap import departure as D
import voe.gap.stages as S
from voe.gap.locate import window_z
from voe.gap.shooting import Shooter
from voe.gap.recordings import Episode
from voe.gap.synth import nominal_motion, pose_noise
out = sys.argv[1]
for spec in sys.argv[2:]:
    seed, truth, nk = spec.split(':'); seed = int(seed)
    case = make_case(np.random.default_rng(seed), truth, noise_kind=nk)
    f = GapFinder(seed=seed)
    p = prepare(case.scene, case.episodes, f.effects, GapConfig())
    rng = np.random.default_rng(seed)
    parts = {}
    orig_dep, orig_more = D.departure_p, D.more_replicates
    def spy(zd, zn, short=None):
        parts['zd'], parts['zn'], parts['short'] = zd, zn, short
        return orig_dep(zd, zn, short)
    def more(scene, episodes, sigma, phi, substep, half, windows, rng, n=D.REPLICATES - 1):
        zero = np.zeros_like(sigma)
        motion = [m + pose_noise(m.shape, zero, 0.0, rng) for m in nominal_motion(scene, episodes, substep)]
        o, o1 = [], []
        long_w = parts['long_windows']
        for _ in range(n):
            eps = [Episode(ep.id, ep.t.copy(), m + pose_noise(m.shape, sigma, phi, rng)) for ep, m in zip(episodes, motion)]
            sh = Shooter(scene, eps, substep, half)
            o.append(window_z(sh, windows, sigma).max(axis=(1, 2)))
            o1.append(window_z(sh, long_w, sigma).max(axis=(1, 2)))
        parts['more_long'] = np.array(o1)
        return np.array(o).reshape(n, len(windows))
    S.departure_p, S.more_replicates = spy, more
    null_eps, finish = locate_parts(p, GapConfig(), rng)
    from voe.gap.shooting import make_windows
    parts['long_windows'] = make_windows(p.episodes, list(range(len(p.episodes))), GapConfig().locate_window, bad_start=p.bad)
    loc = finish()
    S.departure_p, S.more_replicates = orig_dep, orig_more
    zd, zn = parts['zd'], parts['zn']
    sr = D._signed_rank_p(zd, zn); ts = D.tail_p(*parts['short'])
    zn_long = np.vstack([zn[None], parts['more_long']])  # (R, W) the four replicates' 1-s window z
    tl = D.tail_p(zd, zn_long)
    old = min(1.0, 2 * min(sr, ts)); new = min(1.0, 3 * min(sr, ts, tl))
    v_old = 'unexplained' if loc.located and old < D.ALPHA else 'consistent'
    v_new = 'unexplained' if loc.located and new < D.ALPHA else 'consistent'
    np.savez(f'/work/eval/s27/dep/{seed}.npz', zd1=zd, zn1=zn_long, zd05=parts['short'][0], zn05=parts['short'][1], located=len(loc.located), p_main=loc.departure_p)
    r = dict(seed=seed, truth=truth, nk=nk, located=len(loc.located), p_main=loc.departure_p, old=old, new=new, sr=sr, tail_short=ts, tail_long=tl, v_old=v_old, v_new=v_new)
    with open(out, 'a') as fh: fh.write(json.dumps(r) + '\n')
    print(seed, truth, nk, f"located {len(loc.located)} p main {loc.departure_p:.3g} old {old:.3g} new {new:.3g} (sr {sr:.3g} short {ts:.3g} long {tl:.3g})", v_old, '->', v_new, flush=True)
