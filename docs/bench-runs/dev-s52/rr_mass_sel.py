"""rolling_resistance + mass: on the search's own selection windows (per fold, each fold's fitted mass),
the selection SSE of: nominal; mass (fitted, round 1); mass fitted + rr truth; mass truth alone; both truths;
and the round-2 rr fit with the mass refitted on its own windows after rr (one extra block step).

    python rr_mass_sel.py SEED:TRUTH:NOISE
"""
import sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.finder import GapConfig, GapFinder

seed, truth, nk = sys.argv[1].split(":")
case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
print("TRUE", case.true)
f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig(), n_jobs=1).fit(case.scene, case.episodes)
ff = f.search_.fitter
r1 = f.search_.result.rounds[0]
res = r1.results[r1.winner]
print("round 1", r1.winner, "fold params", [p.tolist() for p in res.fold_params])
mass_e = res.effect
rr_e = EFFECTS.get("rolling_resistance")()
(rr_p, _), (m_p, m_b) = case.true["rolling_resistance"], case.true["mass"]
true_mass = EFFECTS.get("mass")(bodies=tuple(m_b))
both = EffectSum((mass_e.parts[0], rr_e))
def sse(e, fold_params):
    return float(ff.heldout_sse(e, fold_params).sum())
nom = sse(None, None)
s_mass = sse(mass_e, res.fold_params)
rows = {
    "nominal": nom,
    "mass fitted": s_mass,
    "mass fitted + rr truth": sse(both, tuple(np.r_[p, rr_p] for p in res.fold_params)),
    "mass truth (its body)": sse(true_mass, tuple(np.asarray(m_p, float) for _ in ff.folds)),
    "mass truth + rr truth": sse(EffectSum((true_mass, rr_e)), tuple(np.r_[m_p, rr_p] for _ in ff.folds)),
}
for k, v in rows.items():
    print(f"{k:28s} sse {v:.4g}  gain vs mass fitted {1 - v / s_mass:+.3f}")
r2 = f.search_.result.rounds[1] if len(f.search_.result.rounds) > 1 else None
if r2 is not None and "rolling_resistance" in r2.results:
    rr_fit = r2.results["rolling_resistance"]
    print("round 2 rr fit fold params", [p.tolist() for p in rr_fit.fold_params], "gain", r2.gains.get("rolling_resistance"))
    # one block step: mass refitted on its own (focused) windows with rr held, per fold
    out = []
    for k, fo in enumerate(ff.folds):
        p = rr_fit.fold_params[k]
        lo, hi = rr_fit.effect.bounds(fo.ctx)
        lo, hi = lo.copy(), hi.copy(); lo[1:], hi[1:] = p[1:], p[1:]
        sub = fo.focused(mass_e, p[:1], *mass_e.bounds(fo.ctx), mass_e.scale(fo.ctx))
        x, c = sub._powell(rr_fit.effect, p, lo, hi, rr_fit.effect.scale(fo.ctx), 40)
        out.append(x)
    print("after mass refit on its windows:", [x.tolist() for x in out], f"sse {sse(rr_fit.effect, tuple(out)):.4g} gain vs mass fitted {1 - sse(rr_fit.effect, tuple(out)) / s_mass:+.3f}")
a = ff.heldout_sse(mass_e, res.fold_params)
b = ff.heldout_sse(EffectSum((true_mass, rr_e)), tuple(np.r_[m_p, rr_p] for _ in ff.folds))
c = ff.heldout_sse(r2.results["rolling_resistance"].effect, r2.results["rolling_resistance"].fold_params) if r2 is not None and "rolling_resistance" in r2.results else a
n0 = ff.heldout_sse(None, None)
print("windows", len(a), "; per window SSE (x1e3): nominal, mass fitted, both truths, round-2 rr fit; start (ep, k0)")
for i in np.argsort(-np.maximum(a, b)):
    w = ff.test[i]
    print(f"  {w.ep:2d} {w.k0:4d}  {n0[i]*1e3:9.3f} {a[i]*1e3:9.3f} {b[i]*1e3:9.3f} {c[i]*1e3:9.3f}")
print("windows where both truths beat mass fitted:", int(np.sum(b < a)), "of", len(a), "; median ratio", float(np.median(b / a)))
