"""Variable projection of start-velocity error (development only): each window's residual with the
span of its start-velocity sensitivities (linearised at the nominal model) projected out, so that
only what no start velocity can mimic is left. rolling_resistance's c_rr chosen on a grid by
the fitting windows' gain (``window_gain``: geometric mean of RMSE ratios), raw and projected, and its gain on the
selection windows, for a case's data and
for clean replicates.

    PYTHONPATH=<clone> python vproj.py SEED TRUTH NOISE_KIND R
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import ALL_EFFECTS
from voe.gap.rollout import run_many
from voe.gap.search import window_gain
from voe.gap.shooting import Shooter
from voe.gap.stages import GapConfig, _bad_starts, fit_windows, prepare
from voe.gap.synth import null_like

DV = np.array([0.01, 0.01, 0.1])  # m/s, m/s, rad/s


def window_bases(sh, wins):
    """Per window an orthonormal basis (N, K) of the residual's sensitivity to the start velocities."""
    starts, times = sh.starts_times(wins)
    base = run_many(sh.scene, starts, times, sh.substep, None, None)
    cols = [[] for _ in wins]
    n_b = len(sh.scene.bodies)
    for b in range(n_b):
        for c in range(3):
            moved = []
            for pose, vel in starts:
                v = vel.copy()
                v[b, c] += DV[c]
                moved.append((pose, v))
            out = run_many(sh.scene, moved, times, sh.substep, None, None)
            for i in range(len(wins)):
                cols[i].append(((out[i] - base[i]) * sh.scale[None]).reshape(-1) / DV[c])
    bases = []
    for cl in cols:
        j = np.stack(cl, axis=1)  # (N, 3B)
        u, s, _ = np.linalg.svd(j, full_matrices=False)
        bases.append(u[:, s > 1e-3 * max(s.max(), 1e-12)])
    return bases


def sse(sh, wins, bases, effect, params):
    raw, proj = [], []
    for w, r, q in zip(wins, sh.residuals(wins, effect, params), bases):
        v = r.reshape(-1)
        raw.append(v @ v)
        e = v - q @ (q.T @ v)
        proj.append(e @ e)
    return np.array(raw), np.array(proj)


def scan(label, p_scene, eps, half, split, config, eff, grid):
    sh = Shooter(p_scene, eps, SUB, half)
    bad = _bad_starts(p_scene, eps, half)
    from voe.gap.shooting import make_windows
    out = {}
    for role, ids in (("fit", split.fit), ("select", split.select)):
        wins = make_windows(eps, list(ids), config.fit_window, bad_start=bad)
        bases = window_bases(sh, wins)
        rows = [sse(sh, wins, bases, eff, np.array([c])) for c in grid]
        out[role] = ([r[0] for r in rows], [r[1] for r in rows])  # per grid value, (W,) each
    res = []
    for k in (0, 1):  # raw, projected
        fit, sel = out["fit"][k], out["select"][k]
        i = int(np.argmax([window_gain(fit[0], f) for f in fit]))
        res.append((grid[i], window_gain(sel[0], sel[i])))
    (cr, gr), (cp, gp) = res
    print(f"{label:14s} raw: fit c {cr:.4f} selection gain {gr:+.3f} | projected: fit c {cp:.4f} selection gain {gp:+.3f}", flush=True)
    return gr, gp


s, truth, kind, reps = int(sys.argv[1]), sys.argv[2], sys.argv[3], int(sys.argv[4])
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
config = GapConfig(second_look=False)
p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
SUB = p.substep
eff = p.candidates["rolling_resistance"]
grid = np.array([0.0, 0.001, 0.002, 0.003, 0.005, 0.0075, 0.01, 0.015, 0.02, 0.03, 0.045, 0.06, 0.08, 0.1, 0.13])
print(s, truth, kind, "true", getattr(case, "params", None), "half", p.half, "split", p.split.fit, p.split.select)
scan("data", p.scene, p.episodes, p.half, p.split, config, eff, grid)
res = []
for i in range(reps):
    eps = null_like(p.scene, p.episodes, p.sigma, np.random.default_rng(10_000 + i), p.substep, p.phi, p.jitter)
    res.append(scan(f"replicate {i}", p.scene, eps, p.half, p.split, config, eff, grid))
if res:
    r = np.array(res)
    print(f"replicates: raw gain > 0.05 in {(r[:, 0] > 0.05).sum()}/{len(r)} max {r[:, 0].max():+.3f}; projected > 0.05 in {(r[:, 1] > 0.05).sum()} max {r[:, 1].max():+.3f}")
