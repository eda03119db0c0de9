"""How much of the speed case's Powell work a looser ftol would skip (no answer changed: a trace only).

For every Powell call: the evaluations (distinct points) after each iteration, the iteration's
cost, and where ftol' in (3e-4, 1e-3, 3e-3) would have stopped instead of 1e-4; the evaluations
that saves, and how far the parameters at that stop are from the final ones (in scale units).
"""
import sys, time, collections
import numpy as np
from scipy.optimize import minimize as _min
from voe.gap import fit as fitmod
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig

calls_log = []

def traced(fun, x0, method=None, options=None, **kw):
    seen = {}
    order = []
    def f(u):
        k = np.asarray(u, float).tobytes()
        v = fun(u)
        if k not in seen:
            seen[k] = v; order.append(k)
        return v
    its = []  # (distinct evals so far, x)
    def cb(xk):
        its.append((len(order), np.array(xk, float)))
    res = _min(f, x0, method=method, options=options, callback=cb, **kw)
    fv = [seen.get(np.asarray(x, float).tobytes()) for _, x in its]
    f0 = seen.get(np.asarray(x0, float).tobytes())
    cl = dict(zip(fun.__code__.co_freevars, (c.cell_contents for c in fun.__closure__)))
    eff = cl.get('effect'); name = '+'.join(type(p).__name__ for p in getattr(eff, 'parts', [eff]))
    calls_log.append(dict(name=name, nfev=res.nfev, status=res.status, maxfev=options.get('maxfev'), n=len(order), its=[(n, fvi, x) for (n, x), fvi in zip(its, fv)], f0=f0, x=np.array(res.x), fun=res.fun, nit=res.nit))
    return res

fitmod.minimize = traced
case = make_case(np.random.default_rng(3), "quadratic_drag", episodes=20, duration=5.0)
t0 = time.process_time()
fnd = GapFinder(seed=0, n_jobs=1, config=GapConfig()).fit(case.scene, case.episodes)
print("effects", [(e['name'], e['params'], e['interval95']) for e in fnd.effects_], "rollouts", fnd.problem_.shooter.n_rollouts, f"cpu {time.process_time()-t0:.1f}")
tot = sum(c['n'] for c in calls_log)
print("powell calls", len(calls_log), "distinct evals", tot, "iters", collections.Counter(c['nit'] for c in calls_log))
for c in calls_log:
    print(f"{c['name']:45s} n={c['n']:3d} nfev={c['nfev']:3d} maxfev={c['maxfev']} nit={c['nit']} status={c['status']}")
for ft in (3e-4, 1e-3, 3e-3):
    saved, dx, dfs = 0, [], []
    for c in calls_log:
        prev = c['f0']
        for n, fv, x in c['its']:
            if fv is None or prev is None:
                prev = fv; continue
            if 2 * (prev - fv) <= ft * (abs(prev) + abs(fv)) + 1e-20:
                saved += c['n'] - n
                dx.append(float(np.max(np.abs(x - c['x']))))
                dfs.append((fv - c['fun']) / max(abs(c['fun']), 1e-300))
                break
            prev = fv
    print(f"ftol {ft:g}: saves {saved} of {tot} evals ({saved/tot:.0%}); stops early in {len(dx)} calls, "
          f"max |dx| (scale units) median {np.median(dx) if dx else 0:.3g} max {max(dx) if dx else 0:.3g}, "
          f"rel cost excess median {np.median(dfs) if dfs else 0:.2e} max {max(dfs) if dfs else 0:.2e}")
