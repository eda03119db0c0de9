"""Step several ``SimWorld``s side by side, with one force evaluation per kick for all of them.

Why: a gap-finder fit simulates thousands of short windows, each in its own small pymunk space,
and almost all of the time went into Python around pymunk, not into pymunk: the ``Space.step``
wrapper, ``Vec2d`` properties, and a numpy force law called on (B,) arrays every 4 ms of
simulated time (a few microseconds of work wrapped in tens of microseconds of overhead). Here
the windows that share an effect and its parameters advance together: every space is stepped by
chipmunk's own ``cpSpaceStep`` and read through its C getters, and at each kick the states of all
spaces are stacked into one ``SimState`` of W*B rows, so the force law runs once per kick instead
of once per window.

Each space still steps alone with exactly the substeps, kicks and arithmetic of
``SimWorld.run`` with a kick function (``voe.gap.rollout``), so a window's prediction is the same
to the last bit as when it is simulated by itself (``tests/gap/test_lockstep.py``).
"""

from __future__ import annotations

import functools
import math
from collections import deque
from collections.abc import Callable
from itertools import compress
from typing import NamedTuple

import numpy as np
import pymunk.batch
from pymunk._chipmunk import ffi, lib

from voe.sim.scenefile import SimState, SimWorld

StackedForce = Callable[[SimState], tuple[np.ndarray, np.ndarray]]

_F = pymunk.batch.BodyFields
_POSE = (_F.POSITION | _F.ANGLE).value  # per body: x, y, angle
_STATE = (_F.POSITION | _F.ANGLE | _F.VELOCITY | _F.ANGULAR_VELOCITY).value  # x, y, angle, vx, vy, omega
_GET = ffi.addressof(lib, "pmSpaceBodyGetIteratorFuncBatched")
_BUFFERS: list[pymunk.batch.Buffer] = []  # reused: pymunk never frees a Buffer's C arrays
_TOUCH = [False]
_SET_V, _SET_W = lib.cpBodySetVelocity, lib.cpBodySetAngularVelocity
_drain = deque(maxlen=0).extend  # runs an iterator of C calls to its end without a Python loop


@ffi.callback("void(cpBody *, cpArbiter *, void *)")
def _on_arbiter(body: object, arb: object, data: object) -> None:
    _TOUCH[0] = True


def schedule(times: np.ndarray, substep: float) -> tuple[tuple[float, ...], tuple[int, ...]]:
    """The substeps ``SimWorld.run`` takes through ``times`` (T,).

    Returns:
        h: length of every substep, in order; ends: after how many substeps each sample k >= 1
        is recorded (T - 1 counts).

    The same numbers as ``SimWorld.run``'s loop (``n = max(1, round(dt / substep))`` substeps of
    ``dt / n``: numpy's round also rounds half to even, and float64 division is IEEE's), computed
    with arrays and remembered per window: a fit simulates the same window hundreds of times.
    """
    return _plan(np.ascontiguousarray(times, dtype=float).tobytes(), float(substep))[:2]


@functools.lru_cache(maxsize=512)  # a 1 s window at 1 ms is ~40 kB here: at most ~20-40 MB
def _plan(times: bytes, substep: float) -> tuple[tuple[float, ...], tuple[int, ...], np.ndarray]:
    """``schedule`` of the float64 ``times`` given as bytes, plus h as a read-only array."""
    dts = np.diff(np.frombuffer(times))  # (T-1,)
    n = np.maximum(1, np.round(dts / substep)).astype(np.int64)  # (T-1,)
    h = np.repeat(dts / n, n)  # (S,)
    h.flags.writeable = False
    return tuple(h.tolist()), tuple(np.cumsum(n).tolist()), h


def _check_steppable(world: SimWorld) -> None:
    """What ``pymunk.Space.step`` would check first (it is bypassed here): finite positive masses,
    and no changes queued for after a step."""
    for b in world.bodies:
        if not (0 < b.mass < math.inf and b.moment > 0):
            raise ValueError(f"lockstep: body with mass {b.mass} and moment {b.moment} cannot be simulated")
    space = world.space
    if space._add_later or space._remove_later or space._post_step_callbacks:  # noqa: SLF001
        raise RuntimeError("lockstep: a space with pending changes or post-step callbacks cannot be stepped in C")


def run_lockstep(worlds: list[SimWorld], times: list[np.ndarray], substep: float, force: StackedForce | None = None,
                 kick_every: float = 4e-3) -> list[np.ndarray]:
    """Step every world through its own ``times`` (T_i,); return poses (T_i, B, 3) per world.

    Args:
        worlds: spaces built from the same scene (same bodies in the same order).
        times: sample times per world, each starting at the world's current state.
        force: maps the stacked state (W*B rows, world by world) to force (W*B, 2) in N and torque
            (W*B,) in N m; it must act row by row (as an effect prepared for the scene tiled W
            times does). None for the nominal scene.
        kick_every: seconds between velocity kicks (impulse = force times the kick interval).
    """
    for w in worlds:
        _check_steppable(w)
    nw = len(worlds)
    if not nw:
        return []
    keys = [(np.ascontiguousarray(t, dtype=float).tobytes(), float(substep)) for t in times]
    plans = [_plan(*k) for k in keys]
    lengths = [len(h) for h, _, _ in plans]
    rows = _rows(worlds)
    bufs = _buffers(nw + 1)  # one per world's poses, one for the kicks' states
    poses = [_Reader(w.space, b, _POSE) for w, b in zip(worlds, bufs, strict=False)]
    for r in poses:
        r.reset()
        r.read()  # the start pose
    k_kick = max(1, round(kick_every / substep))
    kick = _Kick(worlds, force, bufs[nw], rows, _kick_dts([a for _, _, a in plans], lengths, k_kick)) if force is not None else None
    sched = _segments(tuple(keys), k_kick if kick is not None else 0)
    spaces = [worlds[i].space._space for i in sched.order]  # noqa: SLF001
    step, drain, hs = lib.cpSpaceStep, _drain, sched.h
    repeated: dict[tuple[int, int], list] = {}  # (worlds, substeps) -> each space that many times in a row
    for a, n_act, n_sub, lo, hi, reads in sched.segments:
        if kick is not None and a % k_kick == 0:
            kick(a // k_kick)
        args = repeated.get((n_act, n_sub))
        if args is None:
            args = repeated[n_act, n_sub] = [s for s in spaces[:n_act] for _ in range(n_sub)]
        drain(map(step, args, hs[lo:hi]))
        for i in reads:
            poses[i].read()
    nb = len(worlds[0].bodies)
    return [r.array(rows, 3)[:, :nb].copy() for r in poses]


class _Schedule(NamedTuple):
    """The substeps of a lockstep rollout, cut where anything else happens (``_segments``)."""

    order: tuple[int, ...]  # worlds, longest first: the worlds still stepping are a prefix
    h: list[float]  # every substep of every segment, world after world within a segment
    segments: tuple[tuple[int, int, int, int, int, tuple[int, ...]], ...]  # (first substep, worlds
    # stepping, substeps each, slice of ``h``, worlds that record a sample after the segment)


@functools.lru_cache(maxsize=64)  # a fit simulates the same windows side by side dozens of times
def _segments(keys: tuple[tuple[bytes, float], ...], k_kick: int) -> _Schedule:
    """The rollout of the windows with ``_plan`` keys ``keys`` as segments of substeps between
    events (a kick every ``k_kick`` substeps, 0 for none; a sample read; a window's end).

    Why: within a segment nothing but stepping happens, and the worlds are independent spaces,
    so each world can take the segment's substeps one after the other, all of them in one
    ``map`` over chipmunk's ``cpSpaceStep``, instead of one Python loop turn per substep and
    world. Each world still takes exactly its own substeps in its own order, with the kicks
    and reads between the same two substeps as ``SimWorld.run``, so the poses are the same.
    """
    plans = [_plan(*k) for k in keys]
    lengths = [len(h) for h, _, _ in plans]
    order = tuple(sorted(range(len(keys)), key=lambda i: -lengths[i]))
    n = max(lengths)
    record: dict[int, list[int]] = {}  # boundary after substep e - 1 -> worlds that read a sample there
    for i, (_, ends, _) in enumerate(plans):
        for e in ends:
            record.setdefault(e, []).append(i)
    cuts = set(record) | set(lengths) | {0, n}
    if k_kick:
        cuts |= set(range(0, n, k_kick))
    cuts_s = sorted(c for c in cuts if 0 <= c <= n)
    hs = [plans[i][2] for i in order]
    flat: list[float] = []
    segs = []
    for a, b in zip(cuts_s[:-1], cuts_s[1:], strict=True):
        n_act = sum(1 for i in order if lengths[i] > a)
        lo = len(flat)
        for h in hs[:n_act]:
            flat.extend(h[a:b].tolist())
        segs.append((a, n_act, b - a, lo, len(flat), tuple(record.get(b, ()))))
    return _Schedule(order, flat, tuple(segs))


def _kick_dts(hs: list, lengths: list[int], k_kick: int) -> np.ndarray:
    """(K, W) kick interval of every world at each of the K kicks: ``k_kick`` times the substep
    the kick precedes (a world already done keeps its last substep), as ``SimWorld.run`` has it.
    Computed once per rollout instead of at every kick (the same products, to the bit)."""
    at = np.arange(0, max(lengths), k_kick)  # (K,) substep index of each kick
    return np.stack([k_kick * np.asarray(h)[np.minimum(at, n - 1)] for h, n in zip(hs, lengths, strict=True)],
                    axis=1)


def _buffers(n: int) -> list[pymunk.batch.Buffer]:
    while len(_BUFFERS) < n:
        _BUFFERS.append(pymunk.batch.Buffer())
    return _BUFFERS[:n]


class _Reader:
    """Appends fields of every body of one space to a C array, one C call per read."""

    def __init__(self, space: pymunk.Space, buf: pymunk.batch.Buffer, fields: int) -> None:
        self.space, self.arr = space._space, buf._float_arr  # noqa: SLF001
        self.data = ffi.new("pmBatchedData *")
        self.data.fields = fields
        self.data.floatArray, self.data.intArray = buf._float_arr, buf._int_arr  # noqa: SLF001

    def reset(self) -> None:
        self.arr.num = 0

    def read(self) -> None:
        lib.cpSpaceEachBody(self.space, _GET, self.data)

    def array(self, rows: int, width: int) -> np.ndarray:
        """What was read since ``reset``: (reads, rows, width), a view of the C array."""
        return np.frombuffer(ffi.buffer(self.arr.arr, 8 * self.arr.num)).reshape(-1, rows, width)


def _rows(worlds: list[SimWorld]) -> int:
    """Bodies ``cpSpaceEachBody`` visits per space (the dynamic bodies, in ``world.bodies`` order,
    then static ones), checked against the bodies' ids and getters, so a pymunk whose batch layout
    differs fails loudly instead of mixing up bodies. Every world is built by ``SimWorld`` from the
    same scene (the same calls in the same order), so the first world is read in full and the
    others only counted (a fit simulates thousands of windows)."""
    buf = _buffers(1)[0]
    w = worlds[0]
    r = _Reader(w.space, buf, (_F.BODY_ID | _F.POSITION | _F.ANGLE | _F.VELOCITY | _F.ANGULAR_VELOCITY).value)
    r.reset()
    buf._int_arr.num = 0  # noqa: SLF001
    r.read()
    ids = list(memoryview(buf.int_buf()).cast("P"))
    if ids[:len(w.bodies)] != [b.id for b in w.bodies]:
        raise RuntimeError("lockstep: pymunk visits a space's bodies in an unexpected order")
    b = w.bodies[0]
    if r.array(len(ids), 6)[0, 0].tolist() != [*b.position, b.angle, *b.velocity, b.angular_velocity]:
        raise RuntimeError("lockstep: pymunk's batch layout is not x, y, angle, vx, vy, omega")
    if any(len(x.bodies) != len(w.bodies) or x.scene != w.scene for x in worlds[1:]):
        raise RuntimeError("lockstep: the worlds do not hold the same bodies")
    return len(ids)


class _Kick:
    """One velocity kick of every world from one call of the stacked force law.

    The arithmetic per body is ``voe.gap.rollout``'s: v += f * (dt / m), w += tau * dt / I, and a
    body's velocity is written only where its force (or torque) is non-zero.
    """

    def __init__(self, worlds: list[SimWorld], force: StackedForce, buf: pymunk.batch.Buffer, rows: int,
                 dts: np.ndarray) -> None:
        self.force, self.rows = force, rows
        self.readers = [_Reader(w.space, buf, _STATE) for w in worlds]
        self.ptrs = [b._body for w in worlds for b in w.bodies]  # noqa: SLF001
        self.per_world = len(worlds[0].bodies)
        self.mass = np.concatenate([w._mass for w in worlds])  # noqa: SLF001  # (W*B,)
        self.moment = np.concatenate([w._moment for w in worlds])  # noqa: SLF001
        self.gravity = worlds[0]._gravity  # noqa: SLF001
        self._touching: np.ndarray | None = None
        self.dt = np.repeat(dts, self.per_world, axis=1)  # (K, W*B) per kick and body
        self.dt_mass = (self.dt / self.mass)[:, :, None]  # (K, W*B, 1): dt / m, as v += f * (dt / m)
        self.reads = [(r.space, r.data) for r in self.readers]  # one C call per world and kick
        self.arr = buf._float_arr  # noqa: SLF001
        self._view: tuple[object, np.ndarray] | None = None  # (C array it views, (W, rows, 6) view)

    def _contact(self) -> np.ndarray:
        """(W*B,) bool: the body has an arbiter (touches something); computed once per kick."""
        if self._touching is None:
            out = []
            each, touch, cb, null = lib.cpBodyEachArbiter, _TOUCH, _on_arbiter, ffi.NULL
            for ptr in self.ptrs:
                touch[0] = False
                each(ptr, cb, null)
                out.append(touch[0])
            self._touching = np.array(out, dtype=bool)
        return self._touching.copy()

    def _state(self) -> np.ndarray:
        """(W*B, 6) x, y, angle, vx, vy, omega of every body, read now (a fresh array).

        The C array the reads fill is viewed by one numpy array, made at the first kick and
        kept while the array stays where it is: every kick reads the same number of values, so
        pymunk never has to move it after the first (checked at every kick all the same).
        """
        self.arr.num = 0
        each = lib.cpSpaceEachBody
        for space, data in self.reads:
            each(space, _GET, data)
        if self._view is None or self._view[0] != self.arr.arr:
            full = np.frombuffer(ffi.buffer(self.arr.arr, 8 * self.arr.num)).reshape(-1, self.rows, 6)
            self._view = (self.arr.arr, full[:, :self.per_world])  # (W, B, 6)
        return np.array(self._view[1]).reshape(-1, 6)

    def __call__(self, m: int) -> None:
        """Kick ``m`` (its intervals are row ``m`` of the rollout's ``_kick_dts``).

        Velocities are written body by body, and only where the force (torque) is non-zero, as
        ``SimWorld.run`` does. The bodies to write are selected in C (``itertools.compress``), not
        by a Python loop: a body at rest has a zero drag, so in the speed bench's batches 238 of
        250 kicks write only some bodies; when every component is non-zero nothing is selected.
        """
        raw = self._state()  # (N, 6)
        vel = raw[:, 3:5]  # (N, 2)
        self._touching = None
        st = SimState(raw[:, 0:2], vel, raw[:, 2], raw[:, 5], self.mass, self.moment, self.gravity, self._contact)
        f, tau = self.force(st)  # (N, 2), (N,)
        nz = np.count_nonzero(f)
        if nz:
            v_new = (vel + f * self.dt_mass[m]).tolist()  # (N, 2)
            if nz == f.size:
                _drain(map(_SET_V, self.ptrs, v_new))  # every body (the same lengths by construction)
            else:  # the bodies with a non-zero component, selected in C (a body at rest is common)
                on = np.logical_or(f[:, 0], f[:, 1]).tolist()  # (N,)
                _drain(map(_SET_V, compress(self.ptrs, on), compress(v_new, on)))
        nz = np.count_nonzero(tau)
        if nz:
            w_new = (st.omega + tau * self.dt[m] / self.moment).tolist()  # (N,)
            if nz == tau.size:
                _drain(map(_SET_W, self.ptrs, w_new))
            else:
                on = tau.astype(bool).tolist()
                _drain(map(_SET_W, compress(self.ptrs, on), compress(w_new, on)))
