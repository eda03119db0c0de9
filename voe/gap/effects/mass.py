"""Wrong mass: one body's mass and moment scaled by a factor s.

Why: with gravity alone mass does not change a trajectory, but it sets the outcome of collisions
between bodies and the motion of jointed bodies, so the finder fits it one body at a time. Because
it acts only where bodies meet, it is ``sparse``: its fit uses the training windows in which it
changes the prediction (a random subsample held two or three collisions and settled on a mass
ratio on the wrong side of one), and its grid is geometric (a factor of 2 heavier and lighter are
equally far from nominal).
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import Materials, SceneSpec


class Mass(Effect):
    name = "mass"
    mass_proportional = True
    param_names = ("scale",)
    units = ("x nominal",)
    contexts = ("impact",)
    summary = "a body is heavier or lighter than the scene says"
    acts = "contact"
    bench_scene = "arena"
    per_body = True
    sparse = True
    RATIOS = np.array([0.3, 0.5, 0.75, 1.0, 1.35, 2.0, 3.3])  # about x1.5 apart

    def applies(self, scene: SceneSpec) -> bool:
        """Only with two bodies or more: scaling a lone body's mass and moment together changes
        its motion under gravity, contacts with statics and a world pivot not at all; with other
        effects it only rescales their absolute strengths (a damping torque), a false trade-off."""
        return len(scene.bodies) > 1

    def _materials(self, p: np.ndarray, scene: SceneSpec) -> Materials:
        m = self.mask(scene)
        return Materials(mass_scale=tuple(float(p[0]) if k else 1.0 for k in m))

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([1.0])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.2])

    def may_act(self, scene: SceneSpec, pose: np.ndarray) -> bool:
        """Only where one of its bodies comes within 2 cm of another body's bounding circle, or
        is jointed (with gravity and Coulomb friction alone, mass does not change a motion)."""
        m = self.mask(scene)
        names = {b.name for b, k in zip(scene.bodies, m, strict=True) if k}
        if any(j.a in names or j.b in names for j in scene.joints):
            return True
        reach = np.array([np.max(np.linalg.norm(b.local_vertices(), axis=1)) for b in scene.bodies])  # (B,)
        for i in np.flatnonzero(m):
            for j in range(len(scene.bodies)):
                if j != i and np.min(np.linalg.norm(pose[:, i, :2] - pose[:, j, :2], axis=1)) < reach[i] + reach[j] + 0.02:
                    return True
        return False

    def grid(self, x0: float, scale: float) -> np.ndarray:
        return x0 * self.RATIOS

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.05]), np.array([20.0])

    def nominal(self, ctx: FitContext) -> np.ndarray:
        return np.ones(1)

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        return np.array([rng.choice([rng.uniform(0.3, 0.5), rng.uniform(2.0, 3.0)])]), (scene.names[-1],)
