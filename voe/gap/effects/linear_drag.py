"""Linear (viscous, Stokes) drag: F = -c m v.

Why a per-mass coefficient: with gravity alone a body's mass does not enter its trajectory, so
only the deceleration per unit speed, c in 1/s, can be identified from poses.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState


class LinearDrag(Effect):
    name = "linear_drag"
    mass_proportional = True
    param_names = ("c",)
    units = ("1/s",)
    contexts = ("flight",)
    summary = "bodies decelerate in proportion to their speed (linear, viscous drag)"
    bench_scene = "arena"

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return -p[0] * state.mass[:, None] * state.vel, np.zeros_like(state.angle)

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([0.01 / max(ctx.speed, 0.1)])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.1])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([50.0])

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        return np.array([rng.uniform(0.15, 0.5)]), None
