"""Quadratic (air) drag: F = -c m |v| v, with c in 1/m.

Why: at everyday speeds air drag grows with the square of the speed; c = rho Cd A / (2 m).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState


class QuadraticDrag(Effect):
    name = "quadratic_drag"
    mass_proportional = True
    param_names = ("c",)
    units = ("1/m",)
    contexts = ("flight",)
    summary = "bodies decelerate in proportion to speed squared (quadratic air drag)"
    bench_scene = "arena"

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        v = state.vel  # (B, 2)
        # np.linalg.norm(v, axis=1, keepdims=True) to the bit (its own formula for real arrays),
        # without its checks: this runs at every kick of every rollout on top of a fitted drag
        speed = np.sqrt(np.add.reduce(v * v, axis=1, keepdims=True))  # (B, 1)
        return -p[0] * state.mass[:, None] * speed * v, np.zeros_like(state.angle)

    def prepare(self, params: np.ndarray, scene: SceneSpec) -> Callable[[SimState], tuple[np.ndarray, np.ndarray]]:
        """``_forces`` with ``-c m`` (B, 1) and the zero torque kept while the masses stay the same array.

        Why: on top of a fitted drag every rollout of a later round calls this at every kick
        (``voe.sim.lockstep`` passes the same mass array each time); the same products in the
        same order, so the same forces to the bit.
        """
        p = self.check(params)
        mask = self.mask(scene)
        mf = None if mask.all() else mask.astype(float)
        memo: list = [None, None, None]  # mass array, -c m (B, 1), zero torque (B,)

        def force(state: SimState) -> tuple[np.ndarray, np.ndarray]:
            if memo[0] is not state.mass:
                memo[:] = [state.mass, -p[0] * state.mass[:, None], np.zeros_like(state.angle)]
                memo[2].flags.writeable = False
            v = state.vel  # (B, 2)
            f = memo[1] * np.sqrt(np.add.reduce(v * v, axis=1, keepdims=True)) * v
            return (f, memo[2]) if mf is None else (f * mf[:, None], memo[2] * mf)

        return force

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([0.01 / max(ctx.speed, 0.1) ** 2])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.1 / max(ctx.speed, 0.3)])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([50.0])

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        return np.array([rng.uniform(0.05, 0.2)]), None
