"""Deterministic pymunk world built from a ``Scene``, stepped at a fixed frame rate.

Why: concepts need three things from the engine: stepping with fixed substeps, branching one
rollout into two continuations (``copy``, which keeps pymunk's hidden contact state, as STYLE
asks, instead of re-creating bodies), and small law-breaking edits at the violation onset
(remove an object, make it pass through things, switch its gravity off, set its velocity).
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pymunk.batch

from voe.sim.scene import N_FEATURES, Body, Scene, Segment

STATIC_CAT = 0b001  # walls, shelves, ramps
OBJECT_CAT = 0b010
FLOOR_CAT = 0b100  # the ground: separate, so "pass through walls" can keep objects on the floor
ALL_CATS = STATIC_CAT | OBJECT_CAT | FLOOR_CAT
_POSE_FIELDS = (pymunk.batch.BodyFields.BODY_ID | pymunk.batch.BodyFields.POSITION
                | pymunk.batch.BodyFields.ANGLE | pymunk.batch.BodyFields.VELOCITY
                | pymunk.batch.BodyFields.ANGULAR_VELOCITY)


def new_buffer() -> pymunk.batch.Buffer:
    """A ``pymunk.batch.Buffer`` whose C arrays are freed with it.

    Why: pymunk 7.x allocates a Buffer's arrays with ``pmFloatArrayNew``/``pmIntArrayNew`` and
    never frees them, so every clip leaked about 12 KB (``voe world generate`` grew by 14 MB per
    1,000 clips; see ``bench/memory_bench.py``). ``ffi.gc`` attaches the matching free.
    """
    from pymunk._chipmunk import ffi, lib

    buf = pymunk.batch.Buffer()
    buf._float_arr = ffi.gc(buf._float_arr, lib.pmFloatArrayFree)
    buf._int_arr = ffi.gc(buf._int_arr, lib.pmIntArrayFree)
    return buf


def _make_body(spec: Body) -> tuple[pymunk.Body, pymunk.Shape]:
    if spec.shape == "circle":
        moment = pymunk.moment_for_circle(spec.mass, 0, spec.radius)
        body = pymunk.Body(spec.mass, moment)
        shape: pymunk.Shape = pymunk.Circle(body, spec.radius)
    elif spec.shape == "box":
        moment = pymunk.moment_for_box(spec.mass, (spec.width, spec.height))
        body = pymunk.Body(spec.mass, moment)
        shape = pymunk.Poly.create_box(body, (spec.width, spec.height))
    else:  # pragma: no cover - guarded by Body's type
        raise ValueError(f"unknown shape {spec.shape!r}")
    body.position = (spec.x, spec.y)
    body.angle = spec.angle
    body.velocity = (spec.vx, spec.vy)
    body.angular_velocity = spec.omega
    shape.friction = spec.friction
    shape.elasticity = spec.elasticity
    shape.filter = pymunk.ShapeFilter(categories=OBJECT_CAT, mask=ALL_CATS)
    body.voe_spec = spec  # survives Space.copy(); gives slot, shape and look
    body.voe_gravity = True
    return body, shape


def _no_gravity(body: pymunk.Body, gravity, damping, dt) -> None:
    pymunk.Body.update_velocity(body, (0.0, 0.0), damping, dt)


def _remainder_2pi(x: np.ndarray) -> np.ndarray:
    """``math.remainder(x, 2 pi)`` elementwise: ``fmod`` is exact, and so is the one correction
    into ``[-pi, pi]`` (Sterbenz: both operands within a factor 2). An exact tie at +-pi keeps
    the sign of ``fmod``'s result instead of IEEE's even quotient (not reachable in practice)."""
    two_pi = 2 * math.pi
    r = np.fmod(x, two_pi)
    return np.where(r > math.pi, r - two_pi, np.where(r < -math.pi, r + two_pi, r))


class Looks:
    """What the bodies of a space look like, by body id, as sorted arrays for decoding reads.

    Attributes:
        ids: ``(u,)`` sorted body ids (pymunk's ``Body.id``), the space's static body included.
        slot: ``(u,)`` slot of each body, -1 for the static body.
        tails: ``(u, 5)`` constant features ``is_circle .. intensity`` (NaN for the static body).
        box: ``(u,)`` the body is a box (its angle is wrapped into ``[-pi, pi]``).
    """

    def __init__(self, space: pymunk.Space) -> None:
        rows = {space.static_body.id: (-1, (np.nan,) * 5, False)}
        for b in space.bodies:
            spec: Body = b.voe_spec
            tail = (spec.shape == "circle", spec.shape == "box", spec.width, spec.height, spec.intensity)
            rows[b.id] = (spec.slot, tail, spec.shape == "box")
        keys = sorted(rows)
        self.ids = np.array(keys, dtype=np.int64)
        self.slot = np.array([rows[k][0] for k in keys], dtype=np.int64)
        self.tails = np.array([rows[k][1] for k in keys], dtype=np.float64).reshape(-1, 5)
        self.box = np.array([rows[k][2] for k in keys], dtype=bool)


def decode_poses(buf: pymunk.batch.Buffer, frames: list[tuple[int, Looks]], n_slots: int) -> np.ndarray:
    """States ``(T, K, F)`` float64 (NaN rows for missing slots) from ``T`` appended reads.

    Args:
        buf: the buffer ``World.read_poses`` appended to, once per frame.
        frames: per frame, the number of bodies read so far (cumulative) and the looks returned.
    """
    ids = np.frombuffer(buf.int_buf(), dtype=np.int64)  # (M,)
    dyn = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 6)  # (M, 6) x y angle vx vy omega
    out = np.full((len(frames), n_slots, N_FEATURES), np.nan)
    ends = np.array([n for n, _ in frames], dtype=np.int64)
    frame_of = np.repeat(np.arange(len(frames)), np.diff(ends, prepend=0))  # (M,)
    looks_of = [lk for _, lk in frames]
    start = 0
    for f in range(1, len(frames) + 1):  # runs of frames that share one Looks (usually all)
        if f < len(frames) and looks_of[f] is looks_of[start]:
            continue
        a, b, looks = (ends[start - 1] if start else 0), ends[f - 1], looks_of[start]
        at = np.minimum(np.searchsorted(looks.ids, ids[a:b]), len(looks.ids) - 1)  # (m,)
        if not np.array_equal(looks.ids[at], ids[a:b]):
            raise RuntimeError("internal: a pose read names a body its Looks does not know")
        keep = looks.slot[at] >= 0
        at = at[keep]
        rows, cols = frame_of[a:b][keep], looks.slot[at]
        out[rows, cols, :6] = dyn[a:b][keep]
        out[rows, cols, 6:] = looks.tails[at]
        boxes = looks.box[at]
        out[rows[boxes], cols[boxes], 2] = _remainder_2pi(out[rows[boxes], cols[boxes], 2])
        start = f
    return out


class World:
    """A pymunk space plus slot bookkeeping.

    Args:
        scene: initial scene.
        dt: seconds per frame.
        substeps: physics steps per frame.
    """

    def __init__(self, scene: Scene, dt: float, substeps: int) -> None:
        self.scene = scene
        self.dt = dt
        self.substeps = substeps
        self.space = pymunk.Space()
        self.space.gravity = scene.gravity
        self.space.iterations = 20
        self._batch: pymunk.batch.Buffer = new_buffer()
        self._looks: Looks | None = None  # see ``looks``
        for seg in scene.statics:
            self._add_static(seg)
        for spec in scene.bodies:
            self.add(spec)

    # -- construction -------------------------------------------------------------------
    def _add_static(self, seg: Segment) -> None:
        shape = pymunk.Segment(self.space.static_body, seg.a, seg.b, seg.radius)
        shape.friction = seg.friction
        shape.elasticity = seg.elasticity
        cat = FLOOR_CAT if seg.kind == "floor" else STATIC_CAT
        shape.filter = pymunk.ShapeFilter(categories=cat, mask=OBJECT_CAT)
        self.space.add(shape)

    def add(self, spec: Body) -> None:
        """Add a dynamic object in slot ``spec.slot``."""
        body, shape = _make_body(spec)
        self.space.add(body, shape)
        self._looks = None  # rebuilt on the next read: a new body may reuse a removed one's id

    def copy(self) -> World:
        """Branch the rollout: an independent world with identical state, contacts included."""
        new = object.__new__(World)
        new.scene, new.dt, new.substeps = self.scene, self.dt, self.substeps
        new.space = self.space.copy()
        new._batch, new._looks = new_buffer(), None
        return new

    # -- access ------------------------------------------------------------------------
    def bodies(self) -> dict[int, pymunk.Body]:
        """Live dynamic bodies by slot."""
        return {b.voe_spec.slot: b for b in self.space.bodies}

    def body(self, slot: int) -> pymunk.Body:
        return self.bodies()[slot]

    # -- law-breaking edits used at violation onsets and by counterfactual worlds ----------
    def remove(self, slot: int) -> None:
        """Delete the object in ``slot`` (it stops existing)."""
        b = self.body(slot)
        self.space.remove(b, *b.shapes)
        self._looks = None

    def set_passable(self, slot: int, statics: bool = True, objects: bool = True, floor: bool = False) -> None:
        """Let the object pass through walls/shelves/ramps, other objects and/or the floor."""
        mask = (0 if statics else STATIC_CAT) | (0 if objects else OBJECT_CAT) | (0 if floor else FLOOR_CAT)
        for s in self.body(slot).shapes:
            s.filter = pymunk.ShapeFilter(categories=OBJECT_CAT, mask=mask)

    def set_gravity(self, slot: int, on: bool) -> None:
        """Switch gravity on or off for one object."""
        b = self.body(slot)
        b.voe_gravity = on
        b.velocity_func = pymunk.Body.update_velocity if on else _no_gravity

    def set_elasticity(self, slot: int, elasticity: float) -> None:
        """Change how bouncy an object is (above 1, its bounces gain energy)."""
        for s in self.body(slot).shapes:
            s.elasticity = elasticity

    def set_velocity(self, slot: int, vx: float, vy: float, omega: float | None = None) -> None:
        b = self.body(slot)
        b.velocity = (vx, vy)
        if omega is not None:
            b.angular_velocity = omega

    def teleport(self, slot: int, x: float, y: float) -> None:
        b = self.body(slot)
        b.position = (x, y)
        self.space.reindex_shapes_for_body(b)

    # -- stepping and observing ------------------------------------------------------------
    def step(self) -> None:
        """Advance one frame (``substeps`` fixed physics steps)."""
        h = self.dt / self.substeps
        for _ in range(self.substeps):
            self.space.step(h)

    def looks(self) -> Looks:
        """What the bodies now in the space look like. A new object whenever bodies were added or
        removed, so a reference taken now stays valid for the frames read now."""
        if self._looks is None:
            self._looks = Looks(self.space)
        return self._looks

    def read_poses(self, buf: pymunk.batch.Buffer) -> Looks:
        """Append every body's id, x, y, angle, vx, vy, omega to ``buf`` (one C call); returns the
        ``looks`` that decode them (see ``decode_poses``)."""
        pymunk.batch.get_space_bodies(self.space, _POSE_FIELDS, buf)
        return self.looks()

    def poses(self, n_slots: int) -> np.ndarray:
        """True state of every slot now: ``(K, F)`` float64, NaN rows for missing objects."""
        self._batch.clear()
        looks = self.read_poses(self._batch)
        n = len(self._batch.int_buf()) // 8
        return decode_poses(self._batch, [(n, looks)], n_slots)[0]

    def observe(self, n_slots: int) -> np.ndarray:
        """State of every slot now: ``(K, F)`` float32, NaN rows for missing objects."""
        return self.poses(n_slots).astype(np.float32)

    def bboxes(self) -> dict[int, tuple[tuple[float, float], tuple[float, float]]]:
        """Axis-aligned bounding boxes by slot, for occlusion tests."""
        out = {}
        for slot, b in self.bodies().items():
            bbs = [s.cache_bb() for s in b.shapes]
            out[slot] = (
                (min(bb.left for bb in bbs), min(bb.bottom for bb in bbs)),
                (max(bb.right for bb in bbs), max(bb.top for bb in bbs)),
            )
        return out

    def specs(self) -> dict[int, Body]:
        """Current look (shape, size, intensity) of each live slot."""
        return {slot: b.voe_spec for slot, b in self.bodies().items()}
