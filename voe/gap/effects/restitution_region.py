"""Restitution limited to a fitted x-interval: a patch of floor that bounces differently (a rug,
a rubber mat, a dead spot).

Why: a global ``restitution`` fitted to bounces on a patch is wrong for every other bounce, and
the bench's out-of-library floor patches showed that without a region the finder can only say
``unexplained``. The parameters are the floor's elasticity inside the patch and the interval
[x0, x1]; the simulator sets it per contact from the contact point
(``Materials.region_elasticity``, a pre-solve callback), with edges smoothed over 1 cm so the fit
of x0 and x1 stays smooth. Nominal: the floor's own elasticity (then nothing changes).
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import FitContext
from voe.gap.effects.region import _Region, surface_to_bodies
from voe.sim.scenefile import Materials, SceneSpec


def floor_elasticity(scene: SceneSpec) -> float:
    """Mean elasticity of the static segments (the surfaces bounced on)."""
    return float(np.mean([s.elasticity for s in scene.statics])) if scene.statics else 0.0


class RestitutionRegion(_Region):
    name = "restitution_region"
    param_names = ("elasticity", "x0", "x1")
    units = ("", "m", "m")
    contexts = ("region", "impact")
    summary = "bounces between x0 and x1 keep a different fraction of speed (a floor patch)"
    LOW, HIGH, STEP = 0.0, 1.0, 0.1
    global_name = "restitution"

    @property
    def has_forces(self) -> bool:
        return False

    def strengths(self, ctx: FitContext) -> tuple[float, ...]:
        """One strength (half the floor's elasticity: a deader patch, or 0.5 on a dead floor)
        times the four starting intervals. Why one: every start is a fit in every round."""
        fe = floor_elasticity(ctx.scene)
        return (0.5 * fe if fe > 0.2 else 0.5,)

    def _materials(self, p: np.ndarray, scene: SceneSpec) -> Materials:
        return Materials(region_elasticity=(float(p[0]), float(p[1]), float(p[2])))

    def nominal(self, ctx: FitContext) -> np.ndarray:
        return np.array([floor_elasticity(ctx.scene), np.nan, np.nan])

    def unlimited(self, params: np.ndarray, ctx: FitContext) -> np.ndarray | None:
        """The bodies' elasticity that gives their mean bounce on the nominal floor what the patch
        gives it (pymunk multiplies the two); None on a dead floor."""
        return surface_to_bodies(self.check(params)[0], floor_elasticity(ctx.scene),
                                 [b.elasticity for b, m in zip(ctx.scene.bodies, self.mask(ctx.scene), strict=True) if m])
