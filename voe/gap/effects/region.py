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

from collections.abc import Callable

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.gap.effects.rolling_resistance import rolling_force
from voe.sim.scenefile import SceneSpec, SimState

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
    saturates = True  # the body sticks / the ball stops (``Effect.saturates``)
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
        """``forces`` with the radii, |g|, -d_mu |g| and the edges' constants computed once.

        Why: on top of a drag, every rollout of round 2 and of the pair step that carries this
        effect calls it at every kick (about 6 % of ``bench/gap_speed.py``'s CPU). The same
        operations on the same values in the same order as ``_forces`` (|g| of the state's
        gravity, recomputed if another array comes), so the same forces to the bit.
        """
        p = self.check(params)
        radius = np.array([b.radius if b.shape == "circle" else 0.0 for b in scene.bodies])
        self._radius = radius
        m = self.mask(scene)
        mf = None if m.all() else m.astype(float)
        ins = inside_at(p[1], p[2])
        memo: list = [None, 0.0]  # gravity array, -d_mu |g|

        def force(st: SimState) -> tuple[np.ndarray, np.ndarray]:
            if memo[0] is not st.gravity:
                memo[:] = [st.gravity, -p[0] * float(np.linalg.norm(st.gravity))]
            w = st.contact().astype(float) * ins(st.pos[:, 0])  # (B,)
            slip = st.vel.copy()
            slip[:, 0] += st.omega * radius  # contact point below a circle's centre
            n = np.sqrt(np.add.reduce(slip**2, axis=1, keepdims=True) + _V0**2)  # np.sum's reduction
            f = memo[1] * (st.mass * w)[:, None] * slip / n
            tau = radius * f[:, 0]
            return (f, tau) if mf is None else (f * mf[:, None], tau * mf)

        return force

    def forces(self, state, params, scene):
        self._radius = np.array([b.radius if b.shape == "circle" else 0.0 for b in scene.bodies])
        return super().forces(state, params, scene)


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
