"""One window's Gauss-Newton terms with its estimated start velocity profiled out.

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
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.gap.rollout import run_many
from voe.gap.shooting import Shooter, Window

DV = 0.01  # m/s (angular: per sqrt(I/m) metres) finite-difference step of a start velocity
RCOND = 1e-9  # relative cut of the velocity block's pseudo-inverse (a velocity the window never shows)


def profiled_terms(shooter: Shooter, sigma: np.ndarray, w: Window, effect: Effect, params: np.ndarray,
                   ctx: FitContext, f_scale: float = 3.0) -> tuple[np.ndarray, np.ndarray] | None:
    """(P, P) curvature and (P,) gradient of window ``w``'s soft-L1 cost at ``params``, its start
    velocity (B, 3) profiled out; None if the prediction is not finite.

    The parameter columns are those of ``voe.gap.uncertainty.window_terms`` (same steps, same
    weights); the velocity columns step each body's velocity component by ``DV`` (angular ones
    by ``DV`` / sqrt(I/m), so every step moves a pose-equivalent metre scale alike).
    """
    sc, ep = shooter.scene, shooter.episodes[w.ep]
    pose0, vel0 = shooter.initial(w.ep, w.k0)[:2]
    times = ep.t[w.k0:w.k1 + 1]
    wt = shooter.scale[None] / shooter.sigma_pred(w, sigma)  # (n, B, 3) metres, then noise units
    data = ep.pose[w.k0:w.k1 + 1]

    def flat(pred: np.ndarray) -> np.ndarray:
        return ((pred - data) * wt).reshape(-1)

    n_b = vel0.shape[0]
    steps = DV / shooter.scale  # (B, 3) velocity steps
    starts = [(pose0, vel0)]
    for b in range(n_b):
        for j in range(3):
            v = vel0.copy()
            v[b, j] += steps[b, j]
            starts.append((pose0, v))
    runs = run_many(sc, starts, [times] * len(starts), shooter.substep, effect, params)
    r0 = flat(runs[0])
    if not np.all(np.isfinite(r0)):
        return None
    jv = np.stack([(flat(x) - r0) / s for x, s in zip(runs[1:], steps.reshape(-1), strict=True)], axis=1)  # (N, 3B)
    lo_b, hi_b = effect.bounds(ctx)
    scale = effect.scale(ctx)
    jp = np.zeros((r0.size, len(params)))
    for j in range(len(params)):
        step = 0.1 * scale[j]
        up = params[j] + step <= hi_b[j]
        p = params.copy()
        p[j] += step if up else -step
        jp[:, j] = (flat(run_many(sc, [(pose0, vel0)], [times], shooter.substep, effect, p)[0]) - r0) / (step if up else -step)
    shooter.n_rollouts += len(starts) + len(params)
    if not (np.all(np.isfinite(jv)) and np.all(np.isfinite(jp))):
        return None
    irls = 1.0 / np.sqrt(1.0 + (r0 / f_scale) ** 2)  # soft-L1 weights at the fit
    hpp, hpv, hvv = (jp * irls[:, None]).T @ jp, (jp * irls[:, None]).T @ jv, (jv * irls[:, None]).T @ jv
    gp, gv = (jp * irls[:, None]).T @ r0, (jv * irls[:, None]).T @ r0
    k = hpv @ np.linalg.pinv(hvv, rcond=RCOND, hermitian=True)  # (P, 3B)
    return hpp - k @ hpv.T, gp - k @ gv
