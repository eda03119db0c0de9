"""Material effects limited to a fitted x-interval: a patch of floor with other friction or
rolling resistance.

Why: a real floor is rarely uniform (a strip of tape, a worn patch, a rug). A global friction
fitted to a patch is wrong everywhere else, and an unlimited library has no name for it, so the
finder once said "agree" next to a located mismatch. These effects name the patch and bound it:
parameters are the strength and the interval [x0, x1] in which it acts (edges smoothed over
``EDGE`` so the fit stays smooth). Both act only while a body touches something. Friction is
modelled as an extra Coulomb force against the contact point's slip (for a circle, the point
below its centre; otherwise the centre's velocity), with the matching torque on a circle. The
region-limited restitution is ``voe.gap.effects.restitution_region`` (set per contact).
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState

EDGE = 0.01  # m, smoothing of the interval's edges
_V0 = 0.01  # m/s, smoothing speed of the force direction


def inside(x: np.ndarray, x0: float, x1: float) -> np.ndarray:
    """Smooth indicator of x0 <= x <= x1, (B,)."""
    # np.clip's values to the bit (NaN kept), at a third of its cost: this runs at every kick
    a = np.minimum(np.maximum((x - x0) / EDGE, -50.0), 50.0)
    b = np.minimum(np.maximum((x1 - x) / EDGE, -50.0), 50.0)
    return 1.0 / (1.0 + np.exp(-a)) / (1.0 + np.exp(-b))


class _Region(Effect):
    acts = "region"
    contexts = ("region", "sliding", "rolling")
    flight_regression = False
    STRENGTHS: tuple[float, ...] = ()
    LOW, HIGH, STEP = 0.0, 1.0, 0.1
    _radius: np.ndarray | float = 0.0

    def applies(self, scene: SceneSpec) -> bool:
        return bool(scene.statics)

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        lo, hi = float(ctx.lo[0]), float(ctx.hi[0])
        third = (hi - lo) / 3
        spans = [(lo, lo + third), (lo + third, lo + 2 * third), (lo + 2 * third, hi), (lo + 0.75 * third, hi - 0.75 * third)]
        return [np.array([s, a, b]) for s in self.strengths(ctx) for a, b in spans]

    def strengths(self, ctx: FitContext) -> tuple[float, ...]:
        """Starting strengths inside the patch (each times every starting interval)."""
        return self.STRENGTHS

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = float(ctx.lo[0]) - 0.5, float(ctx.hi[0]) + 0.5
        return np.array([self.LOW, lo, lo]), np.array([self.HIGH, hi, hi])

    def scale(self, ctx: FitContext) -> np.ndarray:
        size = float(ctx.hi[0] - ctx.lo[0])
        return np.array([self.STEP, 0.05 * size, 0.05 * size])


class FrictionRegion(_Region):
    name = "friction_region"
    param_names = ("d_mu", "x0", "x1")
    units = ("", "m", "m")
    summary = "sliding contacts between x0 and x1 have a different friction coefficient (a floor patch)"
    STRENGTHS, LOW, HIGH, STEP = (0.3, -0.2), -1.0, 2.0, 0.1
    global_name = "friction"

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        w = state.contact().astype(float) * inside(state.pos[:, 0], p[1], p[2])  # (B,)
        g = float(np.linalg.norm(state.gravity))
        slip = state.vel.copy()
        slip[:, 0] += state.omega * self._radius  # contact point below a circle's centre
        n = np.sqrt(np.sum(slip**2, axis=1, keepdims=True) + _V0**2)
        f = -p[0] * g * (state.mass * w)[:, None] * slip / n
        return f, self._radius * f[:, 0]

    def prepare(self, params, scene):
        self._radius = np.array([b.radius if b.shape == "circle" else 0.0 for b in scene.bodies])
        return super().prepare(params, scene)

    def forces(self, state, params, scene):
        self._radius = np.array([b.radius if b.shape == "circle" else 0.0 for b in scene.bodies])
        return super().forces(state, params, scene)


class RollingResistanceRegion(_Region):
    name = "rolling_resistance_region"
    param_names = ("c_rr", "x0", "x1")
    units = ("", "m", "m")
    summary = "bodies touching the floor between x0 and x1 slow down at a constant rate (a soft patch)"
    STRENGTHS, LOW, HIGH, STEP = (0.05,), 0.0, 1.0, 0.02
    global_name = "rolling_resistance"

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        w = state.contact().astype(float) * inside(state.pos[:, 0], p[1], p[2])  # (B,)
        speed = np.linalg.norm(state.vel, axis=1, keepdims=True)
        g = float(np.linalg.norm(state.gravity))
        return -p[0] * g * (state.mass * w)[:, None] * state.vel / np.sqrt(speed**2 + _V0**2), np.zeros_like(state.angle)
