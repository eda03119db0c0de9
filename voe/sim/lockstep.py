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

import math
from collections.abc import Callable

import numpy as np
from pymunk._chipmunk import lib

from voe.sim.scenefile import SimState, SimWorld

StackedForce = Callable[[SimState], tuple[np.ndarray, np.ndarray]]


def schedule(times: np.ndarray, substep: float) -> tuple[list[float], list[int]]:
    """The substeps ``SimWorld.run`` takes through ``times`` (T,).

    Returns:
        h: length of every substep, in order; ends: after how many substeps each sample k >= 1
        is recorded (T - 1 counts).
    """
    h: list[float] = []
    ends: list[int] = []
    dts = np.diff(times).tolist()
    for dt in dts:
        n = max(1, round(dt / substep))
        h.extend([dt / n] * n)
        ends.append(len(h))
    return h, ends


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
    plans = [schedule(np.asarray(t, dtype=float), substep) for t in times]
    hs = [h for h, _ in plans]
    lengths = [len(h) for h in hs]
    outs = [np.empty((len(t), len(w.bodies), 3)) for w, t in zip(worlds, times, strict=True)]
    for w, o in zip(worlds, outs, strict=True):
        o[0] = _pose(w)
    record: dict[int, list[tuple[int, int]]] = {}  # substep index -> (world, sample) recorded after it
    for i, (_, ends) in enumerate(plans):
        for k, e in enumerate(ends, start=1):
            record.setdefault(e - 1, []).append((i, k))
    order = sorted(range(nw), key=lambda i: -lengths[i])  # worlds still stepping are a prefix of this
    active = [(worlds[i].space._space, hs[i]) for i in order]  # noqa: SLF001
    ends_at = [lengths[i] for i in order]
    k_kick = max(1, round(kick_every / substep))
    kick = _Kick(worlds, force) if force is not None else None
    step = lib.cpSpaceStep
    for j in range(max(lengths, default=0)):
        while ends_at[-1] <= j:  # the shortest window is done
            ends_at.pop()
            active.pop()
        if kick is not None and j % k_kick == 0:
            kick([k_kick * h[min(j, n - 1)] for h, n in zip(hs, lengths, strict=True)])
        for space, h in active:
            step(space, h[j])
        done = record.get(j)
        if done:
            for i, k in done:
                outs[i][k] = _pose(worlds[i])
    return outs


def _pose(world: SimWorld) -> np.ndarray:
    out = np.empty((len(world.bodies), 3))
    for b, row in zip(world.bodies, out, strict=True):
        p = lib.cpBodyGetPosition(b._body)  # noqa: SLF001
        row[0], row[1], row[2] = p.x, p.y, lib.cpBodyGetAngle(b._body)  # noqa: SLF001
    return out


class _Kick:
    """One velocity kick of every world from one call of the stacked force law.

    The arithmetic per body is ``voe.gap.rollout``'s: v += f * (dt / m), w += tau * dt / I, and a
    body's velocity is written only where its force (or torque) is non-zero.
    """

    def __init__(self, worlds: list[SimWorld], force: StackedForce) -> None:
        self.force = force
        self.bodies = [b for w in worlds for b in w.bodies]
        self.ptrs = [b._body for b in self.bodies]  # noqa: SLF001
        self.per_world = len(worlds[0].bodies)
        self.mass = np.concatenate([w._mass for w in worlds])  # noqa: SLF001  # (W*B,)
        self.moment = np.concatenate([w._moment for w in worlds])  # noqa: SLF001
        self.gravity = worlds[0]._gravity  # noqa: SLF001

    def _contact(self) -> np.ndarray:
        out = np.zeros(len(self.bodies), dtype=bool)
        for i, b in enumerate(self.bodies):
            hits: list[int] = []
            b.each_arbiter(lambda arb, h=hits: h.append(1))
            out[i] = bool(hits)
        return out

    def __call__(self, dt_world: list[float]) -> None:
        n = len(self.ptrs)
        raw = np.empty((n, 6))
        get_p, get_v, get_a, get_w = lib.cpBodyGetPosition, lib.cpBodyGetVelocity, lib.cpBodyGetAngle, \
            lib.cpBodyGetAngularVelocity
        for ptr, row in zip(self.ptrs, raw, strict=True):
            p, v = get_p(ptr), get_v(ptr)
            row[0], row[1], row[2], row[3], row[4], row[5] = p.x, p.y, v.x, v.y, get_a(ptr), get_w(ptr)
        vel = raw[:, 2:4]  # (N, 2)
        st = SimState(raw[:, 0:2], vel, raw[:, 4], raw[:, 5], self.mass, self.moment, self.gravity, self._contact)
        f, tau = self.force(st)  # (N, 2), (N,)
        dt = np.repeat(np.asarray(dt_world, dtype=float), self.per_world)  # (N,)
        v_new = (vel + f * (dt / self.mass)[:, None]).tolist()  # (N, 2)
        w_new = (st.omega + tau * dt / self.moment).tolist()  # (N,)
        set_v, set_w = lib.cpBodySetVelocity, lib.cpBodySetAngularVelocity
        for ptr, v, w, fb, tb in zip(self.ptrs, v_new, w_new, f.tolist(), tau.tolist(), strict=True):
            if fb[0] or fb[1]:
                set_v(ptr, v)
            if tb:
                set_w(ptr, w)
