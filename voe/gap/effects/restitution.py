"""Wrong restitution: the bodies' elasticity is a free parameter (pymunk multiplies it with the
elasticity of whatever they hit).

Why: bounce heights are set by the coefficient of restitution, which nominal scenes often guess.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext, body_mask
from voe.sim.scenefile import Materials, SceneSpec


class Restitution(Effect):
    name = "restitution"
    mass_proportional = True
    param_names = ("elasticity",)
    units = ("",)
    contexts = ("impact",)
    summary = "bounces keep a different fraction of speed than the scene says (restitution)"
    acts = "contact"
    bench_scene = "arena"

    def _materials(self, p: np.ndarray, scene: SceneSpec) -> Materials:
        return Materials(elasticity=body_mask(np.full(len(scene.bodies), p[0]), self.mask(scene), None))

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([float(np.mean([b.elasticity for b in ctx.scene.bodies]))])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.1])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([1.0])

    def nominal(self, ctx: FitContext) -> np.ndarray:
        return self.starts(ctx)[0]

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        e = float(np.mean([b.elasticity for b in scene.bodies]))
        return np.array([np.clip(e + rng.choice([-1, 1]) * rng.uniform(0.2, 0.3), 0.05, 0.95)]), None
