"""Fast rollouts of a ``SimWorld`` under an effect: the inner loop of every fit.

Why: a fit simulates thousands of short windows, and with a force effect most of the time went
into Python bookkeeping around each velocity kick (building a full ``SimState``, re-checking the
parameter vector, rebuilding the body mask), not into pymunk. It uses the stepping
loop of ``SimWorld.run`` itself (same substeps, a kick of impulse F * dt_kick before every
``kick_every``-th substep), so recordings simulated with ``SimWorld.run`` and fits made here agree
to rounding, but its kick reads the state with one pass over the bodies and calls a force
function prepared once per rollout (``Effect.prepare``).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.sim.scenefile import SimState, SimWorld

KICK_EVERY = 4e-3  # s, as SimWorld.run

PreparedForce = Callable[[SimState], tuple[np.ndarray, np.ndarray]]


def run(world: SimWorld, times: np.ndarray, substep: float, force: PreparedForce | None = None,
        kick_every: float = KICK_EVERY) -> np.ndarray:
    """Step ``world`` through ``times`` (T,) from ``times[0]``; return poses (T, B, 3).

    Args:
        force: maps the state to (force (B, 2) N, torque (B,) N m); None for the nominal scene.
    """
    if force is None:
        return world.run(times, substep)
    bodies, st0 = world.bodies, world.state()
    return world.run(times, substep, kick_every=kick_every, kick=lambda dt: _kick(bodies, st0, force, dt))


def _kick(bodies: list, st0: SimState, force: PreparedForce, dt: float) -> None:
    vel = np.array([b.velocity for b in bodies])  # (B, 2)
    st = SimState(np.array([b.position for b in bodies]), vel, np.array([b.angle for b in bodies]),
                  np.array([b.angular_velocity for b in bodies]), st0.mass, st0.moment, st0.gravity, st0.contact)
    f, tau = force(st)  # (B, 2), (B,)
    v_new = (vel + f * (dt / st0.mass)[:, None]).tolist()  # (B, 2)
    w_new = (st.omega + tau * dt / st0.moment).tolist()  # (B,)
    for b, v, w, fb, tb in zip(bodies, v_new, w_new, f.tolist(), tau.tolist(), strict=True):
        if fb[0] or fb[1]:
            b.velocity = v
        if tb:
            b.angular_velocity = w
