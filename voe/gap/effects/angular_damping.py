"""Viscous angular damping: torque -b omega on each body, b in N m s/rad.

Why: bearing friction in a pivot, or air resisting a spin, removes rotational energy in
proportion to the angular rate. For a body pivoted to the world this is exactly joint damping.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState


class AngularDamping(Effect):
    name = "angular_damping"
    param_names = ("b",)
    units = ("N m s/rad",)
    contexts = ("swinging", "flight")
    summary = "rotation is damped in proportion to angular rate (viscous joint or spin damping)"
    bench_scene = "arena"

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros_like(state.pos), -p[0] * state.omega

    def _inertia(self, ctx: FitContext) -> float:
        # Inertia about the pivot for jointed bodies, about the COM otherwise.
        vals = []
        for b in ctx.scene.bodies:
            arm2 = max((float(np.sum(np.square(j.anchor_a))) for j in ctx.scene.joints if j.a == b.name), default=0.0)
            vals.append(b.moment_value() + b.mass * arm2)
        return float(np.mean(vals))

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([0.001 * self._inertia(ctx)])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.1 * self._inertia(ctx)])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([1e3 * self._inertia(ctx)])

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        return np.array([rng.uniform(0.3, 1.0) * scene.bodies[0].moment_value() * 3]), None
