"""The template every candidate effect follows, and the ``+`` that combines effects.

Why: the finder treats every hypothesis the same way (fit its parameters, simulate, compare), so
an effect is a small parametric plug-in to the simulator. Following pysindy's feature libraries,
the public methods (``forces``, ``materials``) check the parameter vector and the subclass fills
one private hook (``_forces`` or ``_materials``). ``a + b`` gives an ``EffectSum`` whose parameter
vector is the concatenation of its parts, so ``quadratic_drag + restitution`` is one candidate.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from voe.sim.scenefile import Materials, SceneSpec, SimState

BOUND_TOL = 0.01  # a parameter within 1 % of its bounded range from a bound sits at that bound (``Effect.at_limit``)


@dataclass(frozen=True)
class FitContext:
    """What an effect may know about the problem when proposing starting points and scales.

    Attributes:
        scene: the nominal scene.
        lo, hi: (2,) corners of the box the recorded bodies move in.
        speed: typical recorded speed in m/s.
        omega: typical recorded angular speed in rad/s.
        flight: free-flight samples for regression starting points
            (``voe.gap.prefit.FlightSamples``), or None.
        flight_fine: the same samples smoothed over ``voe.gap.prefit.FINE_HALF`` (a shorter
            span, so a force that changes within a fraction of a second keeps its shape), for
            effects that declare ``fine_flight``; or None.
    """

    scene: SceneSpec
    lo: np.ndarray
    hi: np.ndarray
    speed: float
    omega: float
    flight: object | None = None
    flight_fine: object | None = None


class Effect:
    """Base class of a candidate effect.

    Subclasses set ``name``, ``param_names``, ``units`` and ``contexts`` (the located contexts in
    which the effect is the natural explanation, used to break ties between effects the data
    cannot tell apart) and implement ``_forces`` and/or ``_materials`` plus ``starts``/``scale``.
    """

    name: ClassVar[str] = "effect"
    param_names: ClassVar[tuple[str, ...]] = ()
    units: ClassVar[tuple[str, ...]] = ()
    contexts: ClassVar[tuple[str, ...]] = ()
    summary: ClassVar[str] = ""
    sparse: ClassVar[bool] = False  # acts in few windows only (collisions between bodies): fit where it acts
    # a hinge: once a body sticks or stops, more of the effect predicts the same, so windows that rule out a
    # weaker value can be flat at the fit and a linearised interval cannot see them (voe.gap.profile.nominal_side)
    saturates: ClassVar[bool] = False
    acts: ClassVar[str] = "always"  # when it acts: "always", "contact" (at contacts/impacts), "region", "joint"
    flight_regression: ClassVar[bool] = True  # free-flight accelerations can seed its starts (voe.gap.prefit)
    fine_flight: ClassVar[bool] = False  # also seed from accelerations smoothed over a short span (``FitContext.flight_fine``)
    bench_scene: ClassVar[str | None] = None  # the bench scene it is concealed in ("arena", "pendulum"), or None
    screen_all: ClassVar[bool] = False  # rank its starts on every training window, not a third (voe.gap.fit)
    multi_start: ClassVar[int] = 1  # simulator fits from its this many most promising starts (voe.gap.fit)
    global_name: ClassVar[str | None] = None  # a region effect's unlimited version (voe.gap.search.covers_contacts)
    limit_name: ClassVar[str | None] = None  # the simpler effect it nests as ``limit_params`` run off (``at_limit``)
    limit_params: ClassVar[tuple[int, ...]] = ()  # indices of the parameters whose bound stands for that limit
    # its forces and torques scale with the bodies' masses and moments (accelerations, contact materials), so
    # scaling every mass by one factor leaves the motion unchanged; False where not (a torque -b omega) or not
    # shown (voe.gap.mass_ratio; tests/gap/test_mass_ratio.py checks every True by simulation)
    mass_proportional: ClassVar[bool] = False

    def __init__(self, bodies: tuple[str, ...] | None = None) -> None:
        self.bodies = tuple(bodies) if bodies else None

    # --- parameter bookkeeping -------------------------------------------------------------
    @property
    def n_params(self) -> int:
        return len(self.param_names)

    @property
    def parts(self) -> tuple[Effect, ...]:
        return (self,)

    def check(self, params: np.ndarray) -> np.ndarray:
        """Return ``params`` as a float vector of the right length, or raise ValueError."""
        p = np.asarray(params, dtype=float).reshape(-1)
        if p.shape != (self.n_params,):
            raise ValueError(f"{self.name} takes {self.n_params} parameters {self.param_names}, got {p.shape[0]}")
        if not np.all(np.isfinite(p)):
            raise ValueError(f"{self.name} parameters must be finite, got {p}")
        return p

    def mask(self, scene: SceneSpec) -> np.ndarray:
        """(B,) bool: the bodies this effect acts on."""
        if self.bodies is None:
            return np.ones(len(scene.bodies), dtype=bool)
        return np.array([b.name in self.bodies for b in scene.bodies])

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        """Starting points for the fit (several for effects with a position parameter)."""
        return [np.zeros(self.n_params)]

    def scale(self, ctx: FitContext) -> np.ndarray:
        """(P,) typical parameter magnitudes, for finite differences and ``x_scale``."""
        return np.ones(self.n_params)

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds, (P,) each."""
        return np.full(self.n_params, -np.inf), np.full(self.n_params, np.inf)

    def at_limit(self, params: np.ndarray, ctx: FitContext) -> bool:
        """Whether a fit ``params`` sits at the search bound of a ``limit_params`` parameter, where
        the effect stands in for its nested simpler limit ``limit_name``.

        Why: some effects contain a simpler one as a limit the bounded search cannot reach. A
        spring whose anchor runs off to infinity (stiffness falling as the distance grows) pulls
        with the same force everywhere: ``constant_acceleration``. A fit that stops at the
        anchor's bound (within ``BOUND_TOL`` of the bounded range) was heading for that limit,
        and says nothing about an anchor; ``voe.gap.search.bound_limit`` then names the limit
        when the data cannot tell the two apart.
        """
        if self.limit_name is None:
            return False
        p = self.check(params)
        lo, hi = self.bounds(ctx)
        for i in self.limit_params:
            tol = BOUND_TOL * float(hi[i] - lo[i])
            if p[i] <= lo[i] + tol or p[i] >= hi[i] - tol:
                return True
        return False

    def unlimited(self, params: np.ndarray, ctx: FitContext) -> np.ndarray | None:
        """For a region effect: the parameters of its unlimited form (``global_name``) that act
        everywhere as ``params``' strength acts inside the interval; None for other effects, or
        where no such parameters exist. Used by ``voe.gap.unlimit``.
        """
        return None

    def nominal(self, ctx: FitContext) -> np.ndarray:
        """(P,) parameter values at which the effect changes nothing (NaN where none exists, e.g.
        a position). A fitted effect whose 95 % interval contains its nominal values is not
        established. Default: zero strength in the first parameter, no nominal for the rest."""
        out = np.full(self.n_params, np.nan)
        if self.n_params:
            out[0] = 0.0
        return out

    def applies(self, scene: SceneSpec) -> bool:
        """Whether the effect is a distinct candidate on ``scene`` (e.g. joint effects need joints)."""
        return True

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        """A random concealed strength (and bodies) for the bench, strong enough to matter.

        Effects with a ``bench_scene`` implement it; the bench's truths are read from the registry.
        """
        raise NotImplementedError(f"{self.name} declares no bench prior")

    def may_act(self, scene: SceneSpec, pose: np.ndarray) -> bool:
        """Whether the effect can change a window whose recorded poses are ``pose`` (n, B, 3).

        A cheap geometric screen before ``Fitter.focused`` simulates; most effects act anywhere.
        """
        return True

    def grid(self, x0: float, scale: float) -> np.ndarray:
        """Coarse grid a one-parameter fit starts from, around ``x0``, before its bounded Brent.

        Symmetric reach: a coefficient far below the nominal (friction 0.15 against 0.55) must be
        inside the bracket. Ratio parameters (``mass``) override this with a geometric grid.
        """
        return x0 + scale * np.array([-10.0, -3.0, -1.0, 0.0, 1.0, 3.0, 10.0])

    # --- simulation hooks ------------------------------------------------------------------
    def forces(self, state: SimState, params: np.ndarray, scene: SceneSpec) -> tuple[np.ndarray, np.ndarray]:
        """Extra force (B, 2) in N and torque (B,) in N m on every body at ``state``."""
        p = self.check(params)
        f, tau = self._forces(state, p)
        m = self.mask(scene)
        return f * m[:, None], tau * m

    def materials(self, params: np.ndarray, scene: SceneSpec) -> Materials:
        """Material and mass overrides implied by ``params``."""
        return self._materials(self.check(params), scene)

    @property
    def has_forces(self) -> bool:
        return type(self)._forces is not Effect._forces

    def prepare(self, params: np.ndarray, scene: SceneSpec) -> Callable[[SimState], tuple[np.ndarray, np.ndarray]] | None:
        """``forces`` with the parameters checked and the body mask built once (None if no forces).

        Why: a rollout calls the force function every few milliseconds of simulated time.
        """
        if not self.has_forces:
            return None
        p, hook = self.check(params), self._forces
        m = self.mask(scene)
        if m.all():
            return lambda st: hook(st, p)
        mf = m.astype(float)

        def masked(st: SimState) -> tuple[np.ndarray, np.ndarray]:
            f, tau = hook(st, p)
            return f * mf[:, None], tau * mf

        return masked

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros_like(state.pos), np.zeros_like(state.angle)

    def _materials(self, p: np.ndarray, scene: SceneSpec) -> Materials:
        return Materials()

    def describe(self, params: np.ndarray) -> str:
        """Parameters in words with units, for the explanation."""
        p = self.check(params)
        return ", ".join(f"{n} = {v:.4g} {u}".strip() for n, v, u in zip(self.param_names, p, self.units, strict=True))

    def __add__(self, other: Effect) -> EffectSum:
        return EffectSum(self.parts + other.parts)

    def __repr__(self) -> str:
        return self.name if self.bodies is None else f"{self.name}[{','.join(self.bodies)}]"


class EffectSum(Effect):
    """Several effects acting together; parameters are concatenated in order."""

    name = "sum"

    def __init__(self, parts: tuple[Effect, ...]) -> None:
        super().__init__(None)
        self._parts = tuple(parts)
        self.param_names = tuple(f"{e.name}.{n}" for e in self._parts for n in e.param_names)  # type: ignore[misc]

    @property
    def parts(self) -> tuple[Effect, ...]:
        return self._parts

    @property
    def has_forces(self) -> bool:
        return any(e.has_forces for e in self._parts)

    def prepare(self, params: np.ndarray, scene: SceneSpec) -> Callable[[SimState], tuple[np.ndarray, np.ndarray]] | None:
        fns = [f for e, p in zip(self._parts, self.split(params), strict=True)
               if (f := e.prepare(p, scene)) is not None]
        if not fns:
            return None
        if len(fns) == 1:
            return fns[0]

        def total(st: SimState) -> tuple[np.ndarray, np.ndarray]:
            f, tau = fns[0](st)
            for fn in fns[1:]:
                fe, te = fn(st)
                f, tau = f + fe, tau + te
            return f, tau

        return total

    def split(self, params: np.ndarray) -> list[np.ndarray]:
        """Cut the concatenated vector into one vector per part."""
        p, out, i = self.check(params), [], 0
        for e in self._parts:
            out.append(p[i:i + e.n_params])
            i += e.n_params
        return out

    def forces(self, state: SimState, params: np.ndarray, scene: SceneSpec) -> tuple[np.ndarray, np.ndarray]:
        f, tau = np.zeros_like(state.pos), np.zeros_like(state.angle)
        for e, p in zip(self._parts, self.split(params), strict=True):
            if e.has_forces:
                fe, te = e.forces(state, p, scene)
                f, tau = f + fe, tau + te
        return f, tau

    def materials(self, params: np.ndarray, scene: SceneSpec) -> Materials:
        fr, el, ms = [None] * len(scene.bodies), [None] * len(scene.bodies), np.ones(len(scene.bodies))
        region = region_u = None
        for e, p in zip(self._parts, self.split(params), strict=True):
            m = e.materials(p, scene)
            region = m.region_elasticity if m.region_elasticity is not None else region
            region_u = m.region_friction if m.region_friction is not None else region_u
            for i in range(len(scene.bodies)):
                if m.friction and m.friction[i] is not None:
                    fr[i] = m.friction[i]
                if m.elasticity and m.elasticity[i] is not None:
                    el[i] = m.elasticity[i]
            if m.mass_scale:
                ms = ms * np.asarray(m.mass_scale)
        return Materials(tuple(fr), tuple(el), tuple(float(x) for x in ms), region, region_u)

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        out = [np.zeros(0)]
        for e in self._parts:
            out = [np.concatenate([a, b]) for a in out for b in e.starts(ctx)]
        return out

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.concatenate([e.scale(ctx) for e in self._parts]) if self._parts else np.zeros(0)

    def nominal(self, ctx: FitContext) -> np.ndarray:
        return np.concatenate([e.nominal(ctx) for e in self._parts]) if self._parts else np.zeros(0)

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        b = [e.bounds(ctx) for e in self._parts]
        if not b:
            return np.zeros(0), np.zeros(0)
        return np.concatenate([x[0] for x in b]), np.concatenate([x[1] for x in b])

    def describe(self, params: np.ndarray) -> str:
        return "; ".join(f"{e.name}: {e.describe(p)}" for e, p in zip(self._parts, self.split(params), strict=True))

    def __repr__(self) -> str:
        return " + ".join(repr(e) for e in self._parts) or "none"


def body_mask(values: np.ndarray, mask: np.ndarray, fill: float | None) -> tuple[float | None, ...]:
    """Per-body tuple with ``values`` where ``mask`` and ``fill`` elsewhere."""
    return tuple(float(v) if m else fill for v, m in zip(values, mask, strict=True))
