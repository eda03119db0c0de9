"""Dev: a constant acceleration added to the model as a nuisance; does its per-window estimate change in time?"""
import sys, json
import numpy as np
from voe.gap.bench import make_case
from voe.gap import drift as D
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.stages import GapConfig, prepare, fit_context
from voe.gap.shooting import make_windows
from voe.gap.nuisance import profiled_terms
from voe.gap.uncertainty import window_terms
from voe.gap.finder import ALL_EFFECTS

def terms_for(p, eff, params, cfg):
    length = cfg.fit_window / 2
    ws = make_windows(p.episodes, list(p.split.fit), length, stride=length / 2, bad_start=p.bad)
    ctx = fit_context(p)
    prof = None if p.shooter.scene.joints else profiled_terms(p.shooter, p.sigma, ws, eff, params, ctx, cfg.fit.f_scale)
    kept, terms = [], []
    for i, w in enumerate(ws):
        if prof is not None:
            t = prof[i]
        else:
            h, g, _ = window_terms(p.shooter, p.sigma, [w], eff, params, ctx, cfg.fit.f_scale)
            t = (h[0], g[0]) if len(h) else None
        if t is not None:
            kept.append(w); terms.append(t)
    hs, gs = np.stack([t[0] for t in terms]), np.stack([t[1] for t in terms])
    eps = p.shooter.episodes
    mid = np.array([0.5 * (eps[w.ep].t[w.k0] + eps[w.ep].t[w.k1]) - eps[w.ep].t[0] for w in kept])
    return hs, gs, mid, ctx

def ca_tests(hs, gs, params, mid, scale, seed=0, kinds=("slot", "cp")):
    slot = np.round(mid / D.SLOT).astype(int)
    sl = slice(len(params) - 2, len(params))
    splits = []
    if "slot" in kinds:
        splits += [(f"slot {a*D.SLOT:.2f}", slot == a) for a in np.unique(slot)]
    if "cp" in kinds:
        splits += [(f"cp {a*D.SLOT:.2f}", slot < a) for a in np.unique(slot)[1:]]
    rng = np.random.default_rng(seed)
    n_tests = 2 * len(splits)
    res = []
    for name, mask in splits:
        r = D.split_estimates(hs, gs, params, mask, sl, rng, None, scale[sl], slot)
        if r is None: continue
        a, b, sd = r
        z = np.abs(a - b) / np.maximum(sd, 1e-300)
        df = min(int(mask.sum()), int((~mask).sum())) - 1
        c = D.critical(df, n_tests)
        for j in range(2):
            res.append((round(float(z[j] / c), 2), name, "xy"[j], round(float(a[j]), 3), round(float(b[j]), 3), round(float(z[j]), 1)))
    res.sort(reverse=True)
    return res, n_tests

def run(seed, truth, name=None, params=None):
    cfg = GapConfig()
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind="white")
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
    if name is None:  # the truth at its true parameters
        parts = [EFFECTS.get(n)(bodies=b) for n, (pp, b) in case.true.items()]
        params = np.concatenate([pp for n, (pp, b) in case.true.items()])
    else:
        parts = [EFFECTS.get(name)()]
    ca = EFFECTS.get("constant_acceleration")()
    eff = EffectSum(tuple(parts) + (ca,))
    pr = np.concatenate([np.asarray(params, float), [0.0, 0.0]])
    hs, gs, mid, ctx = terms_for(p, eff, pr, cfg)
    res, n = ca_tests(hs, gs, pr, mid, eff.scale(ctx), seed)
    return res, n, len(mid)

if __name__ == "__main__":
    seed, truth = int(sys.argv[1]), sys.argv[2]
    name = sys.argv[3] if len(sys.argv) > 3 else None
    params = [float(x) for x in sys.argv[4:]] if len(sys.argv) > 4 else None
    res, n, w = run(seed, truth, name, params)
    print(seed, truth, name, "windows", w, "tests", n, "top z/crit", res[:4])
