"""Material effects limited to a fitted x-interval: a patch of floor with other friction or
rolling resistance.

Why: a real floor is rarely uniform (a strip of tape, a worn patch, a rug). A global friction
fitted to a patch is wrong everywhere else, and an unlimited library has no name for it, so the
finder once said "agree" next to a located mismatch. These effects name the patch and bound it:
parameters are the strength and the interval [x0, x1] in which it acts (edges smoothed over
``EDGE`` so the fit stays smooth). Both act only while a body touches something. Friction is
the floor's coefficient inside the interval, set per contact by the simulator
(``Materials.region_friction``); rolling resistance is a force against the velocity. The
region-limited restitution is ``voe.gap.effects.restitution_region`` (set per contact too).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.gap.effects.rolling_resistance import rolling_force
from voe.sim.scenefile import Materials, SceneSpec, SimState

EDGE = 0.01  # m, smoothing of the interval's edges
_V0 = 0.01  # m/s, smoothing speed of the force direction


def inside(x: np.ndarray, x0: float, x1: float) -> np.ndarray:
    """Smooth indicator of x0 <= x <= x1, (B,)."""
    # np.clip's values to the bit (NaN kept), at a third of its cost: this runs at every kick
    a = np.minimum(np.maximum((x - x0) / EDGE, -50.0), 50.0)
    b = np.minimum(np.maximum((x1 - x) / EDGE, -50.0), 50.0)
    return 1.0 / (1.0 + np.exp(-a)) / (1.0 + np.exp(-b))


def inside_at(x0: float, x1: float) -> Callable[[np.ndarray], np.ndarray]:
    """``inside(x, x0, x1)`` as a function of x (B,), the same values to the bit in 8 numpy calls
    instead of 16: both edges in one (2, B) array.

    Why exact: the exponents are -a = clip((x - x0) / -EDGE) and -b = clip((x - x1) / EDGE), since
    negating a difference, a quotient's divisor or a clip with symmetric bounds only flips signs
    (IEEE rounding is symmetric; a zero's sign does not change exp's 1), and np.exp gives an
    element the same value in any array (``tests/gap/test_speed4.py``). Only a NaN x (a diverged
    rollout) may come out as a NaN of the other sign bit, which no later operation can see.
    """
    at = np.array([[x0], [x1]], dtype=float)  # (2, 1)
    den = np.array([[-EDGE], [EDGE]])

    def ins(x: np.ndarray) -> np.ndarray:
        e = 1.0 + np.exp(np.minimum(np.maximum((x - at) / den, -50.0), 50.0))  # (2, B)
        return 1.0 / e[0] / e[1]

    return ins


class _Region(Effect):
    acts = "region"
    mass_proportional = True  # as the material effects it limits to an interval
    contexts = ("region", "sliding", "rolling")
    flight_regression = False
    STRENGTHS: tuple[float, ...] = ()
    LOW, HIGH, STEP = 0.0, 1.0, 0.1
    EDGE_GRID = 0  # if set, starting intervals also join points of a grid of this many steps over the x range

    def applies(self, scene: SceneSpec) -> bool:
        return bool(scene.statics)

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        lo, hi = float(ctx.lo[0]), float(ctx.hi[0])
        third = (hi - lo) / 3
        spans = [(lo, lo + third), (lo + third, lo + 2 * third), (lo + 2 * third, hi), (lo + 0.75 * third, hi - 0.75 * third)]
        if self.EDGE_GRID:  # narrower patches: every interval joining points of a grid, up to a quarter of the range
            edges = np.linspace(lo, hi, self.EDGE_GRID + 1)  # (EDGE_GRID + 1,)
            spans += [(float(edges[i]), float(edges[i + k])) for k in range(1, self.EDGE_GRID // 4 + 1)
                      for i in range(self.EDGE_GRID + 1 - k)]
        return [np.array([s, a, b]) for s in self.strengths(ctx) for a, b in spans]

    def strengths(self, ctx: FitContext) -> tuple[float, ...]:
        """Starting strengths inside the patch (each times every starting interval)."""
        return self.STRENGTHS

    def unlimited(self, params: np.ndarray, ctx: FitContext) -> np.ndarray | None:
        """The strength itself: a force law (``rolling_resistance``) takes the same coefficient."""
        return self.check(params)[:1]

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = float(ctx.lo[0]) - 0.5, float(ctx.hi[0]) + 0.5
        return np.array([self.LOW, lo, lo]), np.array([self.HIGH, hi, hi])

    def scale(self, ctx: FitContext) -> np.ndarray:
        size = float(ctx.hi[0] - ctx.lo[0])
        return np.array([self.STEP, 0.05 * size, 0.05 * size])


def surface_to_bodies(inside: float, floor: float, bodies: list[float]) -> np.ndarray | None:
    """(1,) the bodies' coefficient c with c * floor = mean(bodies) * inside: a patch's surface
    coefficient ``inside`` as a material effect on the bodies (pymunk multiplies the body's and
    the surface's), or None when the floor's own is zero."""
    if floor <= 0 or not bodies:
        return None
    return np.array([float(np.mean(bodies)) * inside / floor])


def floor_friction(scene: SceneSpec) -> float:
    """Mean friction coefficient of the static segments (the surfaces slid on)."""
    return float(np.mean([s.friction for s in scene.statics])) if scene.statics else 0.0


class FrictionRegion(_Region):
    """The floor's friction coefficient inside [x0, x1], set per contact by the simulator.

    Why per contact and not a force: a patch changes the contact's coefficient, static friction
    included, so a box that reaches a sticky patch stops and tips about its leading edge, and a
    ball's spin is caught. Session 33 traced the seed-6774 floor patches (floor 1.0, patch 2.7 and
    2.9 over about 1 m) with the earlier form, a Coulomb force against the slip at the body's
    centre: at the true interval no strength gained on the fitting windows (train gain below
    6 %, negative on one), so the finder could only say ``consistent`` or name a global
    ``friction`` as a stand-in. Pymunk multiplies the body's and the surface's coefficients;
    this sets the surface's, as ``friction`` sets the bodies'. Nominal: the floor's own.
    """

    name = "friction_region"
    saturates = True  # the body sticks / the ball stops (``Effect.saturates``)
    param_names = ("friction", "x0", "x1")
    units = ("", "m", "m")
    summary = "sliding contacts between x0 and x1 have a different friction coefficient (a floor patch)"
    global_name = "friction"
    # a sticky patch of 1 m in an 8.6 m range changes little unless an interval near it starts the
    # fit: the four thirds-wide spans never reached the seed-6774 patches (session 33), which gain
    # 21-26 % on the selection windows at their true intervals; the screen (cost on every fitting
    # window, ``Effect.screen_all``) ranks these cheaply and only the best is fitted
    EDGE_GRID = 12
    screen_all = True

    @property
    def has_forces(self) -> bool:
        return False

    def strengths(self, ctx: FitContext) -> tuple[float, ...]:
        """A slicker and a stickier patch, half and twice the floor's coefficient (0.5 and 1 on a
        frictionless floor), each times the four starting intervals."""
        fu = floor_friction(ctx.scene)
        return (0.5 * fu, 2.0 * fu) if fu > 0.25 else (0.5, 1.0)

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = super().bounds(ctx)
        hi[0] = 4.0 * max(floor_friction(ctx.scene), 0.5)  # up to four times the floor's grip
        return lo, hi

    def scale(self, ctx: FitContext) -> np.ndarray:
        out = super().scale(ctx)
        out[0] = 0.1 * max(floor_friction(ctx.scene), 0.5)
        return out

    def _materials(self, p: np.ndarray, scene: SceneSpec) -> Materials:
        return Materials(region_friction=(float(p[0]), float(p[1]), float(p[2])))

    def nominal(self, ctx: FitContext) -> np.ndarray:
        return np.array([floor_friction(ctx.scene), np.nan, np.nan])

    def unlimited(self, params: np.ndarray, ctx: FitContext) -> np.ndarray | None:
        """The bodies' coefficient that gives their mean contact coefficient with the nominal floor
        what the patch gives it (pymunk multiplies the two); None on a frictionless floor."""
        return surface_to_bodies(self.check(params)[0], floor_friction(ctx.scene),
                                 [b.friction for b, m in zip(ctx.scene.bodies, self.mask(ctx.scene), strict=True) if m])


class RollingResistanceRegion(_Region):
    name = "rolling_resistance_region"
    saturates = True  # the body sticks / the ball stops (``Effect.saturates``)
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

    def prepare(self, params, scene):
        """``forces`` with -c_rr |g|, the edges' constants and the zero torque computed once
        (``rolling_resistance.rolling_force``, weighted by the contact test times ``inside_at``),
        the same forces to the bit."""
        p = self.check(params)
        ins = inside_at(p[1], p[2])
        return rolling_force(p[0], self.mask(scene), lambda st: st.contact().astype(float) * ins(st.pos[:, 0]))
