"""Wrong mass: one body's mass and moment scaled by a factor s.

Why: with gravity alone mass does not change a trajectory, but it sets the outcome of collisions
between bodies and the motion of jointed bodies, so the finder fits it one body at a time.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import Materials, SceneSpec


class Mass(Effect):
    name = "mass"
    param_names = ("scale",)
    units = ("x nominal",)
    contexts = ("impact",)
    summary = "a body is heavier or lighter than the scene says"
    per_body = True

    def _materials(self, p: np.ndarray, scene: SceneSpec) -> Materials:
        m = self.mask(scene)
        return Materials(mass_scale=tuple(float(p[0]) if k else 1.0 for k in m))

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([1.0])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.2])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.05]), np.array([20.0])
