"""Rolling resistance: while touching something, a force c m |g| against the motion.

Why: a ball rolling on a real table slows down at a nearly constant rate (deformation of the ball
and the surface), which a rigid-body contact does not produce. The direction is smoothed below
1 cm/s so the force vanishes at rest instead of chattering.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState

_V0 = 0.01  # m/s, smoothing speed of the direction


class RollingResistance(Effect):
    name = "rolling_resistance"
    mass_proportional = True
    saturates = True  # the body sticks / the ball stops (``Effect.saturates``)
    param_names = ("c_rr",)
    units = ("",)
    contexts = ("rolling",)
    summary = "bodies in contact slow down at a constant rate (rolling resistance)"
    acts = "contact"
    bench_scene = "arena"

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        touching = state.contact().astype(float)  # (B,)
        v = state.vel  # (B, 2)
        speed = np.sqrt(np.add.reduce(v * v, axis=1, keepdims=True))  # (B, 1) np.linalg.norm's formula, cheaper per kick
        g = float(np.linalg.norm(state.gravity))
        f = -p[0] * g * (state.mass * touching)[:, None] * state.vel / np.sqrt(speed**2 + _V0**2)
        return f, np.zeros_like(state.angle)

    def prepare(self, params: np.ndarray, scene: SceneSpec) -> Callable[[SimState], tuple[np.ndarray, np.ndarray]]:
        """``_forces`` with -c_rr |g| and the zero torque kept while the state brings the same
        gravity and shape (the same operations in the same order: the same forces to the bit)."""
        return rolling_force(self.check(params)[0], self.mask(scene), lambda st: st.contact().astype(float))

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([0.001])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.02])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([1.0])

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        return np.array([rng.uniform(0.03, 0.1)]), None


def rolling_force(c_rr: float, mask: np.ndarray, weight: Callable[[SimState], np.ndarray]
                  ) -> Callable[[SimState], tuple[np.ndarray, np.ndarray]]:
    """The rolling-resistance force law -c_rr |g| m w v / sqrt(|v|^2 + V0^2) with -c_rr |g| and the
    zero torque computed once per gravity array and shape; ``weight(st)`` (B,) says where it acts
    (the contact test, times the region's profile for ``rolling_resistance_region``), ``mask`` (B,)
    which bodies it applies to. One closure for both effects' ``prepare``: the same operations in
    the same order as their ``_forces``, so the same forces to the bit (``tests/gap/test_speed4.py``)."""
    mf = None if mask.all() else mask.astype(float)
    memo: list = [None, 0.0, None]  # gravity array, -c_rr |g|, zero torque

    def force(st: SimState) -> tuple[np.ndarray, np.ndarray]:
        if memo[0] is not st.gravity or memo[2].shape != st.angle.shape:
            memo[:] = [st.gravity, -c_rr * float(np.linalg.norm(st.gravity)), np.zeros_like(st.angle)]
            memo[2].flags.writeable = False
        w = weight(st)  # (B,)
        v = st.vel  # (B, 2)
        speed = np.sqrt(np.add.reduce(v * v, axis=1, keepdims=True))  # (B, 1)
        f = memo[1] * (st.mass * w)[:, None] * v / np.sqrt(speed**2 + _V0**2)
        return (f, memo[2]) if mf is None else (f * mf[:, None], memo[2] * mf)

    return force
