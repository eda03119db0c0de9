"""A window's estimated start velocity as a nuisance: profiled out of its Gauss-Newton terms, or
projected out of its residual.

Why: a window starts from a state estimated from the recording (``voe.gap.shooting.local_state``),
and its velocity error can look like an effect. A rolling ball makes this systematic: its linear
and angular velocities are estimated separately, the angle ten times noisier, so the estimate
breaks the rolling constraint; the simulated ball slips, friction removes the slip within a few
milliseconds, and the ball leaves at a speed the estimate did not say. Over half a second that is
the signature of a drag. On development case 1531045 (a true linear drag, c = 0.183) the four
windows centred 2.5 s into the episodes, where the ball rolls, gave c = 0.119 (their real
optimum too, scanned, not a linearisation artefact). From the true start states the same
windows fit 0.183; from the estimated states with only the ball's true angular velocity (ep 2)
or true linear velocity (ep 4) put back, they prefer 0.183 again. The drift test
(``voe.gap.drift``) read that as a drag changing in time (z = 9.8) and dropped the right effect.

Profiling (the Schur complement of the velocity block of the window's curvature) asks what the
window says about the parameters whatever its start velocity, as a fit that also freed the
start velocity would.

Projecting (``projected_sse``) asks the same of a window's error itself: what is left of the
residual once every change a start-velocity error could make is taken out. ``voe.gap.profile``
asks a saturating part's nominal value with it (see ``voe.gap.profile.nominal_side``).
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.gap.rollout import run_many
from voe.gap.shooting import Shooter, Window

DV = 0.01  # m/s (angular: per sqrt(I/m) metres) finite-difference step of a start velocity
RCOND = 1e-9  # relative cut of the velocity block's pseudo-inverse (a velocity the window never shows)
BASIS_RCOND = 1e-3  # relative cut of a window's velocity sensitivities (directions it barely shows)


def stepped_starts(shooter: Shooter, windows: list[Window]) -> tuple[list[tuple[np.ndarray, np.ndarray]],
                                                                     list[np.ndarray], np.ndarray]:
    """Each window's start (pose (B, 3), velocity (B, 3)) followed by the same start with one
    velocity component stepped (``DV`` per pose-equivalent metre: angular steps ``DV`` / sqrt(I/m)),
    1 + 3B starts per window; each window's sample times (n_i,); and the (3B,) steps."""
    steps = (DV / shooter.scale).reshape(-1)  # (3B,) velocity steps
    starts, times = [], []
    for w in windows:
        pose0, vel0 = shooter.initial(w.ep, w.k0)[:2]
        times.append(shooter.episodes[w.ep].t[w.k0:w.k1 + 1])
        starts.append((pose0, vel0))
        for i, dv in enumerate(steps):
            v = vel0.copy().reshape(-1)
            v[i] += dv
            starts.append((pose0, v.reshape(vel0.shape)))
    return starts, times, steps


def profiled_terms(shooter: Shooter, sigma: np.ndarray, windows: list[Window], effect: Effect, params: np.ndarray,
                   ctx: FitContext, f_scale: float = 3.0) -> list[tuple[np.ndarray, np.ndarray] | None]:
    """Per window, the (P, P) curvature and (P,) gradient of its soft-L1 cost at ``params``, its
    start velocity (B, 3) profiled out; None for a window whose prediction is not finite.

    The parameter columns are those of ``voe.gap.uncertainty.window_terms`` (same steps, same
    weights); the velocity columns step each body's velocity component by ``DV`` (angular ones
    by ``DV`` / sqrt(I/m), so every step moves a pose-equivalent metre scale alike). All windows
    and steps are simulated side by side (``run_many``): 1 + 3B + P rollouts per window.
    """
    sc = shooter.scene
    starts, times, steps = stepped_starts(shooter, windows)
    n_v = steps.size
    data = [shooter.episodes[w.ep].pose[w.k0:w.k1 + 1] for w in windows]
    wts = [shooter.scale[None] / shooter.sigma_pred(w, sigma) for w in windows]  # (n, B, 3) metres, then noise units
    rep = [t for t in times for _ in range(1 + n_v)]
    runs = run_many(sc, starts, rep, shooter.substep, effect, params)  # (1 + 3B) per window
    lo_b, hi_b = effect.bounds(ctx)
    scale = effect.scale(ctx)
    moved, dps = [], []
    for j in range(len(params)):
        step = 0.1 * scale[j]
        dp = step if params[j] + step <= hi_b[j] else -step
        p = params.copy()
        p[j] += dp
        moved.append(run_many(sc, starts[::1 + n_v], times, shooter.substep, effect, p))
        dps.append(dp)
    shooter.n_rollouts += len(starts) + len(params) * len(windows)
    out: list[tuple[np.ndarray, np.ndarray] | None] = []
    for i in range(len(windows)):
        def flat(pred: np.ndarray, i: int = i) -> np.ndarray:
            return ((pred - data[i]) * wts[i]).reshape(-1)

        r0 = flat(runs[i * (1 + n_v)])
        jv = np.stack([(flat(runs[i * (1 + n_v) + 1 + k]) - r0) / steps[k] for k in range(n_v)], axis=1)
        jp = np.stack([(flat(moved[j][i]) - r0) / dps[j] for j in range(len(params))], axis=1)  # (N, P)
        if not (np.all(np.isfinite(r0)) and np.all(np.isfinite(jv)) and np.all(np.isfinite(jp))):
            out.append(None)
            continue
        irls = 1.0 / np.sqrt(1.0 + (r0 / f_scale) ** 2)  # soft-L1 weights at the fit
        jpw, jvw = jp * irls[:, None], jv * irls[:, None]
        hpv, hvv = jpw.T @ jv, jvw.T @ jv
        k = hpv @ np.linalg.pinv(hvv, rcond=RCOND, hermitian=True)  # (P, 3B)
        out.append((jpw.T @ jp - k @ hpv.T, jpw.T @ r0 - k @ (jvw.T @ r0)))
    return out


def velocity_bases(shooter: Shooter, windows: list[Window], effect: Effect | None,
                   params: np.ndarray | None) -> list[np.ndarray | None]:
    """Per window an orthonormal basis (N, K) of how its residual (flattened (n, B, 3), metres)
    moves with its start velocity, linearised under ``effect`` at ``params``; None for a window
    whose prediction is not finite. The starts are ``stepped_starts``' (``DV`` per pose-equivalent
    metre), all simulated side by side: 1 + 3B rollouts per window. Directions whose singular
    value is below ``BASIS_RCOND`` of the window's largest are left out (a body at rest that
    friction stops at once)."""
    starts, times, steps = stepped_starts(shooter, windows)
    rep = [t for t in times for _ in range(1 + steps.size)]
    runs = run_many(shooter.scene, starts, rep, shooter.substep, effect, params)
    shooter.n_rollouts += len(starts)
    out: list[np.ndarray | None] = []
    for i in range(len(windows)):
        base = runs[i * (1 + steps.size)] * shooter.scale[None]  # (n, B, 3)
        cols = np.stack([((runs[i * (1 + steps.size) + 1 + k] * shooter.scale[None]) - base).reshape(-1) / dv
                         for k, dv in enumerate(steps)], axis=1)  # (N, 3B)
        if not np.all(np.isfinite(cols)):
            out.append(None)
            continue
        u, s, _ = np.linalg.svd(cols, full_matrices=False)
        out.append(u[:, s > BASIS_RCOND * max(float(s.max()), 1e-300)])
    return out


def projected_sse(shooter: Shooter, windows: list[Window], bases: list[np.ndarray | None], effect: Effect | None,
                  params: np.ndarray | None) -> np.ndarray:
    """(W,) each window's sum of squared residuals (``voe.gap.shooting.window_sse``) with its
    start-velocity directions ``bases`` (``velocity_bases``) projected out; a window without a
    basis keeps its plain sum."""
    out = []
    for r, q in zip(shooter.residuals(windows, effect, params), bases, strict=True):
        v = r.reshape(-1)
        e = v if q is None else v - q @ (q.T @ v)
        out.append(float(e @ e))
    return np.array(out)
