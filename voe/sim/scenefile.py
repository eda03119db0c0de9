"""Build a gap-finder ``scene.json`` into a pymunk space and step it with external forces.

Why: the gap finder compares recordings with a nominal simulation and with simulations that
carry candidate effects. Only ``voe.sim`` imports pymunk, so this module owns the space: it
builds bodies, statics and pivot joints from plain frozen specs, exposes the state as numpy
arrays, and lets callers add forces and torques and change materials without touching pymunk.

Pivot joints get ``error_bias = 0`` (full position correction every step). With pymunk's default
bias the impulse solver loses energy at a rate proportional to the step (a frictionless arm
started at 1.6 rad loses 0.033 J in 5 s at 1 ms steps, as much as a real bearing), which hides
joint damping. With full correction the loss at 1 ms drops below 1 mJ in 5 s, so a damping fitted
through this simulator matches the exact ODE to about 2 %.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pymunk
from pymunk._chipmunk import ffi, lib


@dataclass(frozen=True)
class BodySpec:
    """One dynamic body. ``size`` is [w, h] for boxes; ``vertices`` are local, COM at origin."""

    name: str
    shape: str  # "circle" | "box" | "poly"
    mass: float
    radius: float = 0.0
    size: tuple[float, float] = (0.0, 0.0)
    vertices: tuple[tuple[float, float], ...] = ()
    moment: float | None = None
    friction: float = 0.5
    elasticity: float = 0.0

    def local_vertices(self) -> np.ndarray:
        """Outline points in the body frame, (V, 2); a circle gives 16 rim points."""
        if self.shape == "circle":
            a = np.linspace(0, 2 * np.pi, 16, endpoint=False)
            return self.radius * np.stack([np.cos(a), np.sin(a)], axis=1)
        if self.shape == "box":
            w, h = self.size
            return np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
        return np.asarray(self.vertices, dtype=float)

    def moment_value(self) -> float:
        """The given moment, or pymunk's moment for a uniform shape."""
        if self.moment is not None:
            return float(self.moment)
        if self.shape == "circle":
            return pymunk.moment_for_circle(self.mass, 0, self.radius)
        if self.shape == "box":
            return pymunk.moment_for_box(self.mass, self.size)
        return pymunk.moment_for_poly(self.mass, [tuple(v) for v in self.vertices])

    @property
    def gyration_radius(self) -> float:
        """sqrt(I / m): converts an angle error to a comparable length in metres."""
        return math.sqrt(self.moment_value() / self.mass)


@dataclass(frozen=True)
class StaticSpec:
    """A static segment (ground, wall, ramp)."""

    a: tuple[float, float]
    b: tuple[float, float]
    radius: float = 0.0
    friction: float = 0.5
    elasticity: float = 0.0


@dataclass(frozen=True)
class JointSpec:
    """A pivot joint with anchors in each body's local frame (``b`` None means the world)."""

    a: str
    b: str | None
    anchor_a: tuple[float, float]
    anchor_b: tuple[float, float]
    collide_bodies: bool = False


@dataclass(frozen=True)
class SceneSpec:
    """A whole nominal scene; joints must already have local anchors resolved."""

    gravity: tuple[float, float]
    bodies: tuple[BodySpec, ...]
    statics: tuple[StaticSpec, ...] = ()
    joints: tuple[JointSpec, ...] = ()
    units: dict = field(default_factory=dict, compare=False, hash=False)

    @property
    def names(self) -> list[str]:
        return [b.name for b in self.bodies]

    def jointed(self) -> np.ndarray:
        """(B,) bool: body takes part in a joint (its motion is 'swinging')."""
        names = {j.a for j in self.joints} | {j.b for j in self.joints if j.b}
        return np.array([b.name in names for b in self.bodies])


@dataclass
class SimState:
    """Numpy view of all dynamic bodies at one instant. Shapes: (B, 2) and (B,)."""

    pos: np.ndarray
    vel: np.ndarray
    angle: np.ndarray
    omega: np.ndarray
    mass: np.ndarray
    moment: np.ndarray
    gravity: np.ndarray  # (2,)
    contact: Callable[[], np.ndarray]  # lazy (B,) bool: touching anything


ForceFn = Callable[[SimState], tuple[np.ndarray, np.ndarray]]


@dataclass(frozen=True)
class Materials:
    """Per-body overrides applied at build time by effects (None keeps the scene value)."""

    friction: tuple[float | None, ...] | None = None
    elasticity: tuple[float | None, ...] | None = None
    mass_scale: tuple[float, ...] | None = None
    # (e, x0, x1): static surfaces have elasticity e at contact points with x0 <= x <= x1
    # (edges smoothed over 1 cm), set per contact (``voe.gap.effects.restitution_region``)
    region_elasticity: tuple[float, float, float] | None = None
    # (u, x0, x1): static surfaces have friction u there, the same way (``voe.gap.effects.region``)
    region_friction: tuple[float, float, float] | None = None


class SimWorld:
    """A pymunk space built from a ``SceneSpec`` at a given state.

    Args:
        scene: the nominal scene.
        pose: (B, 3) x, y, angle of each body's COM.
        vel: (B, 3) vx, vy, omega.
        materials: per-body material and mass overrides.
    """

    def __init__(self, scene: SceneSpec, pose: np.ndarray, vel: np.ndarray,
                 materials: Materials | None = None, contacts: list | None = None) -> None:
        """Build the space. ``contacts``: a list that every contact with a static segment that a
        region material would be set for (``_region_pre``'s contacts) is appended to, as (x of the
        contact point, the segment's friction, its elasticity), while nothing is changed; only
        for a world without region materials (``region_inert``)."""
        self.scene = scene
        mat = materials or Materials()
        self.space = pymunk.Space()
        # pymunk's setters are these C calls (in this order); called directly, as a fit builds
        # thousands of worlds (``voe.gap.rollout.run_many``)
        lib.cpSpaceSetGravity(self.space._space, tuple(scene.gravity))  # noqa: SLF001
        self.bodies: list[pymunk.Body] = []
        for i, spec in enumerate(scene.bodies):
            scale = mat.mass_scale[i] if mat.mass_scale else 1.0
            body = pymunk.Body(spec.mass * scale, _moment(spec) * scale)
            b = body._body  # noqa: SLF001
            lib.cpBodySetPosition(b, (float(pose[i, 0]), float(pose[i, 1])))
            lib.cpBodySetAngle(b, float(pose[i, 2]))
            lib.cpBodySetVelocity(b, (float(vel[i, 0]), float(vel[i, 1])))
            lib.cpBodySetAngularVelocity(b, float(vel[i, 2]))
            if spec.shape == "circle":
                shape = pymunk.Circle(body, spec.radius)
            else:
                shape = pymunk.Poly(body, _outline(spec))
            lib.cpShapeSetFriction(shape._shape, _pick(mat.friction, i, spec.friction))  # noqa: SLF001
            lib.cpShapeSetElasticity(shape._shape, _pick(mat.elasticity, i, spec.elasticity))  # noqa: SLF001
            self.space.add(body, shape)
            self.bodies.append(body)
        for st in scene.statics:
            seg = pymunk.Segment(self.space.static_body, st.a, st.b, st.radius)
            lib.cpShapeSetFriction(seg._shape, st.friction)  # noqa: SLF001
            lib.cpShapeSetElasticity(seg._shape, st.elasticity)  # noqa: SLF001
            lib.cpShapeSetCollisionType(seg._shape, _STATIC)  # noqa: SLF001
            self.space.add(seg)
        has_region = mat.region_elasticity is not None or mat.region_friction is not None
        if has_region and contacts is not None:
            raise ValueError("SimWorld: contacts are recorded only without region materials")
        if has_region:  # chipmunk's own handler (_region_pre)
            nan3 = (math.nan,) * 3  # a material not set (not read by its pre_solve)
            region = ffi.new("double[6]", (*(mat.region_elasticity or nan3), *(mat.region_friction or nan3)))
            self.space._voe_region = region  # lives as long as the space that points at it
            handler = lib.cpSpaceAddCollisionHandler(self.space._space, _STATIC, _WILDCARD)  # noqa: SLF001
            ks = (0,) * (mat.region_elasticity is not None) + (3,) * (mat.region_friction is not None)
            handler.preSolveFunc, handler.userData = _REGION_PRE[ks], region
        elif contacts is not None:
            self.space._voe_contacts = keep = ffi.new_handle(contacts)  # alive as long as the space
            handler = lib.cpSpaceAddCollisionHandler(self.space._space, _STATIC, _WILDCARD)  # noqa: SLF001
            handler.preSolveFunc, handler.userData = _region_record, keep
        index = {n: i for i, n in enumerate(scene.names)}
        for js in scene.joints:
            other = self.space.static_body if js.b is None else self.bodies[index[js.b]]
            joint = pymunk.PivotJoint(self.bodies[index[js.a]], other, js.anchor_a, js.anchor_b)
            joint.collide_bodies = js.collide_bodies
            joint.error_bias = 0.0
            self.space.add(joint)
        self._mass = np.array([b.mass for b in self.bodies])
        self._moment = np.array([b.moment for b in self.bodies])
        self._gravity = np.array(scene.gravity, dtype=float)

    def state(self) -> SimState:
        """Current state as numpy arrays."""
        bs = self.bodies
        pos = np.array([tuple(b.position) for b in bs])
        vel = np.array([tuple(b.velocity) for b in bs])
        return SimState(pos, vel, np.array([b.angle for b in bs]), np.array([b.angular_velocity for b in bs]),
                        self._mass, self._moment, self._gravity, self._contacts)

    def _contacts(self) -> np.ndarray:
        out = np.zeros(len(self.bodies), dtype=bool)
        for i, b in enumerate(self.bodies):
            hits: list[int] = []
            b.each_arbiter(lambda arb, h=hits: h.append(1))
            out[i] = bool(hits)
        return out

    def pose(self) -> np.ndarray:
        """(B, 3) x, y, angle."""
        return np.array([(b.position.x, b.position.y, b.angle) for b in self.bodies])

    def run(self, times: np.ndarray, substep: float, force_fn: ForceFn | None = None,
            kick_every: float = 4e-3, kick: Callable[[float], None] | None = None) -> np.ndarray:
        """Step through ``times`` (T,), starting at times[0]; return poses (T, B, 3).

        External forces from ``force_fn`` are applied as velocity kicks (impulse = force times
        ``kick_every``) once per ``kick_every`` seconds. Why: evaluating Python forces and
        setting pymunk forces every 1 ms substep made effect rollouts ten times slower than
        nominal ones; a kick every few milliseconds is a first-order splitting with the same
        order of accuracy as holding the force. ``kick(dt)`` replaces the kick from ``force_fn``
        (the gap finder's fast rollouts bring their own, with the same schedule).
        """
        if kick is None and force_fn is not None:
            kick = lambda dt: self._kick(force_fn, dt)  # noqa: E731
        out = np.empty((len(times), len(self.bodies), 3))
        out[0] = self.pose()
        k_kick = max(1, round(kick_every / substep))
        step = self.space.step
        count = 0
        for k in range(1, len(times)):
            n = max(1, round((times[k] - times[k - 1]) / substep))
            h = (times[k] - times[k - 1]) / n
            for _ in range(n):
                if kick is not None and count % k_kick == 0:
                    kick(k_kick * h)
                count += 1
                step(h)
            out[k] = self.pose()
        return out

    def _kick(self, force_fn: ForceFn, dt: float) -> None:
        st = self.state()
        f, tau = force_fn(st)  # (B, 2), (B,)
        dv = f * (dt / st.mass)[:, None]  # (B, 2)
        dw = tau * dt / st.moment  # (B,)
        for b, (dvx, dvy), w in zip(self.bodies, dv.tolist(), dw.tolist(), strict=True):
            if dvx or dvy:
                v = b.velocity
                b.velocity = (v.x + dvx, v.y + dvy)
            if w:
                b.angular_velocity = b.angular_velocity + w


_STATIC = 1  # collision type of static segments


_WILDCARD = int(ffi.cast("uintptr_t", ~0))  # chipmunk's CP_WILDCARD_COLLISION_TYPE (what pymunk passes for None)


def _region_pre(ks: tuple[int, ...]) -> object:
    """The pre_solve of a space built with ``Materials.region_elasticity`` (``ks`` holds 0) or
    ``region_friction`` (``ks`` holds 3), or both: restitution (friction) of a contact with a
    static segment, blended from the segment's elasticity (friction) to ``e`` (``u``) inside
    [x0, x1] (smooth edges keep a fit of x0, x1 smooth); ``data`` points at the world's
    (e, x0, x1, u, ux0, ux1). Chipmunk sets the arbiter's ``e`` and ``u`` from the two shapes
    before every pre_solve, so what is set here holds for this step only, as pymunk's
    ``Arbiter.friction`` setter does.

    Why this form: it runs at every substep of every resting contact (about 1700 calls per
    simulated second of a ball and a box on the floor), and registered through
    ``Space.on_collision`` with pymunk's getters it cost more than the rest of the rollout. Here
    chipmunk calls it directly and it reads the arbiter's fields, as chipmunk's own getters do:
    ``cpArbiterGetCount`` (no points once cached), ``cpArbiterGetShapes`` and the first point's
    ``pointA`` of ``cpArbiterGetContactPointSet`` (the static segment's side, in the handler's
    order: the arbiter's second shape when it is swapped), and ``cpArbiterSetRestitution`` (``SetFriction``). The
    clip of the edge terms keeps ``max(-50, min(50, v))``'s semantics. Same values to the bit
    (``tests/gap/test_lockstep.py``). One function per set of materials, so a call tests
    nothing about the material that is not set (a patch's start screen makes millions of calls).
    """

    @ffi.callback("void(cpArbiter *, cpSpace *, void *)")
    def pre(arb: object, space: object, data: object, cast=ffi.cast, exp=math.exp,
            cached=lib.CP_ARBITER_STATE_CACHED, position=lib.cpBodyGetPosition,
            elasticity=lib.cpShapeGetElasticity, friction=lib.cpShapeGetFriction, ks=ks) -> None:
        if arb.state == cached or not arb.count:
            return
        p = cast("double *", data)
        if arb.swapped:
            seg, other = arb.b, arb.a
            x = position(arb.body_b).x + arb.contacts[0].r2.x
        else:
            seg, other = arb.a, arb.b
            x = position(arb.body_a).x + arb.contacts[0].r1.x
        for k in ks:  # p[0]: restitution, p[3]: friction
            v = (x - p[k + 1]) / 0.01
            v = v if v < 50.0 else 50.0
            v = v if v > -50.0 else -50.0
            w = 1.0 / (1.0 + exp(-v))
            v = (p[k + 2] - x) / 0.01
            v = v if v < 50.0 else 50.0
            v = v if v > -50.0 else -50.0
            w /= 1.0 + exp(-v)
            if k:
                seg_u = friction(seg)
                arb.u = friction(other) * (seg_u + w * (p[3] - seg_u))
            else:
                seg_e = elasticity(seg)
                arb.e = elasticity(other) * (seg_e + w * (p[0] - seg_e))

    return pre


_REGION_PRE = {ks: _region_pre(ks) for ks in ((0,), (3,), (0, 3))}  # materials set -> pre_solve


@ffi.callback("void(cpArbiter *, cpSpace *, void *)")
def _region_record(arb: object, space: object, data: object, cached=lib.CP_ARBITER_STATE_CACHED,
                   position=lib.cpBodyGetPosition, elasticity=lib.cpShapeGetElasticity,
                   friction=lib.cpShapeGetFriction, from_handle=ffi.from_handle) -> None:
    """pre_solve of a space built with ``contacts``: appends what ``_region_pre`` would read of
    each contact it sets a material for (the same contacts, the same x), changing nothing."""
    if arb.state == cached or not arb.count:
        return
    if arb.swapped:
        seg, x = arb.b, position(arb.body_b).x + arb.contacts[0].r2.x
    else:
        seg, x = arb.a, position(arb.body_a).x + arb.contacts[0].r1.x
    from_handle(data).append((x, friction(seg), elasticity(seg)))


def region_weight(x: np.ndarray, x0: float, x1: float) -> np.ndarray:
    """(N,) ``_region_pre``'s weight of the region [x0, x1] at contact points x (N,), in numpy
    (its exponentials may differ from ``math.exp``'s in the last bit)."""
    a = np.minimum(np.maximum((x - x0) / 0.01, -50.0), 50.0)
    b = np.minimum(np.maximum((x1 - x) / 0.01, -50.0), 50.0)
    return 1.0 / (1.0 + np.exp(-a)) / (1.0 + np.exp(-b))


def region_inert(contacts: np.ndarray, materials: Materials) -> bool:
    """Whether ``materials``' region materials leave a rollout exactly as it was without them,
    given ``contacts`` (N, 3) recorded by a world built without them (``SimWorld(contacts=...)``).

    Why this is exact: the two rollouts are the same until ``_region_pre`` first sets a
    coefficient other than chipmunk's own (the product of the two shapes'), and it sets
    ``other * (seg + w * (v - seg))``, which is ``other * seg`` to the bit when ``w * (v - seg)``
    is below half a unit in the last place of ``seg`` (the gap below a power of two is half the
    one above: ``np.spacing`` / 4). If it is below an eighth at every recorded contact (so a
    last-bit difference between numpy's and ``math.exp`` cannot matter; a zero coefficient never
    passes), no contact is set differently, and by induction over the substeps the
    rollouts are the same: the same contacts at the same points. A window that touches the floor
    only far from a patch, or not at all, need not be simulated again (``voe.gap.bare``).
    """
    if materials.region_elasticity is None and materials.region_friction is None:
        return True
    x = contacts[:, 0]  # (N,)
    for region, seg in ((materials.region_friction, contacts[:, 1]), (materials.region_elasticity, contacts[:, 2])):
        if region is None or not len(x):
            continue
        v, x0, x1 = region
        moved = np.abs(region_weight(x, x0, x1) * (v - seg))  # (N,)
        if not bool(np.all((seg > 0) & (moved < np.spacing(seg) / 8))):  # NaN fails too
            return False
    return True


@functools.lru_cache(maxsize=256)
def _moment(spec: BodySpec) -> float:
    """``spec.moment_value()``, remembered per body spec (frozen)."""
    return spec.moment_value()


@functools.lru_cache(maxsize=256)
def _outline(spec: BodySpec) -> list[tuple[float, float]]:
    """``spec.local_vertices()`` as the list of tuples ``pymunk.Poly`` takes, remembered per spec
    (pymunk copies the points into C; the list is not kept)."""
    return [tuple(v) for v in spec.local_vertices()]


def _pick(values: tuple[float | None, ...] | None, i: int, default: float) -> float:
    if values is None or values[i] is None:
        return default
    return float(values[i])
