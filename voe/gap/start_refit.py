"""A window's start velocity refitted under a model: what the window says once start noise is given back.

Why: a window restarts from a velocity read off the recording by a local cubic fit
(``voe.gap.shooting.local_state``). Its error, about 7 mm/s per millimetre of noise at +-12 samples
and 25 mm/s at +-5, is small in free flight. A collision in the window amplifies it, and then the
true physics itself departs from the recording. On development cases 3829037, 6056094 and 3829008,
restarted from the noise-free start, the truth followed the noise-free poses to 0.1 mm, 0.0 mm and
4.5 mm. Restarted from the start read off the recording (velocity errors of 14-47 mm/s, about two
sigmas), it departed by 49, 145 and 348 mm (docs/bench-runs/dev-s63/start_bias.txt). A test window
that departs only because of its start is no evidence against the model. Refitting the start
velocity under the model, with the start fit's own error as a Gaussian prior (a MAP estimate), takes
that departure out. Missing or wrong physics stays: a start velocity moves a path linearly in time,
but a force moves it quadratically. ``voe.gap.carry_over.deepened`` asks this before it blames a model
for a window.
"""

from __future__ import annotations

import numpy as np

from voe.gap import locate
from voe.gap.effects.base import Effect
from voe.gap.rollout import run_many
from voe.gap.shooting import ORDER, Shooter, Window

ITERATIONS = 10  # Levenberg-Marquardt steps at most (each 1 + 3B rollouts for the Jacobian, then up to TRIES)
TRIES = 6  # damping increases per step before it gives up
STEP = 0.3  # finite-difference step of a start velocity component, in its own prior sigmas


def start_sigma(shooter: Shooter, win: Window, sigma: np.ndarray) -> np.ndarray:
    """(B, 3) standard error of the window's start velocity as ``local_state`` reads it: the variance
    of the slope of its least-squares polynomial (order ``ORDER``, the same samples) for noise
    ``sigma`` (B, 3)."""
    ep = shooter.episodes[win.ep]
    n = min(len(ep.t), max(2 * shooter.half + 1, ORDER + 3))
    lo = min(max(0, win.k0 - n // 2), len(ep.t) - n)
    tt = ep.t[lo:lo + n] - ep.t[win.k0]  # (n,)
    span = max(float(np.max(np.abs(tt))), 1e-9)  # as local_state, time scaled to [-1, 1] for conditioning
    x = np.vander(tt / span, ORDER + 1)  # (n, ORDER + 1), the slope is the second-last column
    return sigma * float(np.sqrt(np.linalg.pinv(x.T @ x)[-2, -2])) / span


def window_z(shooter: Shooter, win: Window, pred: np.ndarray, sigma: np.ndarray) -> float:
    """The window's largest z over bodies and variables (``voe.gap.locate.window_z``'s statistic, as
    ``deepened`` reads it) for predicted poses ``pred`` (n, B, 3)."""
    res = (pred - shooter.episodes[win.ep].pose[win.k0:win.k1 + 1]) * shooter.scale[None]  # (n, B, 3)
    return float(locate.window_z(shooter, [win], sigma, [res]).max())


def refitted(shooter: Shooter, win: Window, effect: Effect | None, params: np.ndarray | None,
             sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(predicted poses (n, B, 3), velocity change (B, 3)) of the window restarted from its MAP start
    velocity under ``effect`` at ``params``: Levenberg-Marquardt on the window's standardised residual
    (``sigma_pred``) plus the change over its ``start_sigma``. The start pose stays as read. Deterministic.
    """
    pose0, vel0 = shooter.initial(win.ep, win.k0)[:2]
    t = shooter.episodes[win.ep].t[win.k0:win.k1 + 1]
    data = shooter.episodes[win.ep].pose[win.k0:win.k1 + 1]
    wt = shooter.scale[None] / shooter.sigma_pred(win, sigma)  # (n, B, 3)
    sv = start_sigma(shooter, win, sigma).reshape(-1)  # (3B,)
    live = np.flatnonzero(sv > 0)

    def residuals(dvs: list[np.ndarray]) -> tuple[list[np.ndarray], list[np.ndarray]]:
        starts = [(pose0, vel0 + dv.reshape(vel0.shape)) for dv in dvs]
        preds = run_many(shooter.scene, starts, [t] * len(dvs), shooter.substep, effect, params)
        shooter.n_rollouts += len(dvs)
        return [np.concatenate([((p - data) * wt)[1:].reshape(-1), dv[live] / sv[live]])
                for p, dv in zip(preds, dvs, strict=True)], preds

    dv = np.zeros(vel0.size)
    (r,), (pred,) = residuals([dv])
    if not np.all(np.isfinite(r)):
        return pred, dv.reshape(vel0.shape)
    cost, lam = float(r @ r), 1e-2
    basis = np.eye(dv.size)
    for _ in range(ITERATIONS):
        steps = STEP * sv[live]
        rs, _ = residuals([dv] + [dv + basis[k] * s for k, s in zip(live, steps, strict=True)])
        jac = np.stack([(rs[1 + i] - rs[0]) / s for i, s in enumerate(steps)], axis=1)  # (N, L)
        if not np.all(np.isfinite(jac)):
            break
        h, g = jac.T @ jac, jac.T @ rs[0]
        for _ in range(TRIES):
            cand = dv.copy()
            cand[live] -= np.linalg.solve(h + lam * np.diag(np.diag(h) + 1e-12), g)
            (rc,), (pc,) = residuals([cand])
            if np.all(np.isfinite(rc)) and float(rc @ rc) < cost:
                dv, cost, pred, lam = cand, float(rc @ rc), pc, lam / 3
                break
            lam *= 10
        else:
            break
    return pred, dv.reshape(vel0.shape)


def refitted_z(shooter: Shooter, win: Window, effect: Effect | None, params: np.ndarray | None,
               sigma: np.ndarray) -> float:
    """``window_z`` of the window restarted from its MAP start velocity under the model (``refitted``)."""
    return window_z(shooter, win, refitted(shooter, win, effect, params, sigma)[0], sigma)
