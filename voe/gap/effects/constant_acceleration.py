"""A constant extra acceleration (ax, ay): a uniform wind, a tilted table or a wrong gravity.

Why one family: all three add the same uniform acceleration field, so poses cannot tell them
apart; the finder reports the vector and leaves the physical reading to the user.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState


class ConstantAcceleration(Effect):
    name = "constant_acceleration"
    mass_proportional = True
    param_names = ("ax", "ay")
    units = ("m/s^2", "m/s^2")
    contexts = ("flight", "sliding", "rolling")
    summary = "every body feels the same extra constant acceleration (wind, tilted table or wrong gravity)"
    bench_scene = "arena"

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return state.mass[:, None] * p[None, :], np.zeros_like(state.angle)

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.3, 0.3])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([-50.0, -50.0]), np.array([50.0, 50.0])

    def nominal(self, ctx: FitContext) -> np.ndarray:
        return np.zeros(2)

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        a, th = rng.uniform(0.3, 1.0), rng.uniform(0, 2 * np.pi)
        return np.array([a * np.cos(th), a * np.sin(th)]), None
