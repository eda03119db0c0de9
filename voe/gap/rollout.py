"""Fast rollouts of windows under an effect: the inner loop of every fit.

Why: a fit simulates thousands of short windows, and nearly all of the time went into Python
around pymunk (the ``Space.step`` wrapper, ``Vec2d`` properties, building a ``SimState`` and
calling a numpy force law on (B,) arrays at every kick), not into pymunk. ``run_many`` steps the
windows that share an effect and its parameters side by side (``voe.sim.lockstep``): each space is
stepped in C, and at each kick one call of the force law, prepared once for the scene tiled W
times (``Effect.prepare``), serves all W windows. Substeps, kicks (an impulse F * dt_kick before
every ``kick_every``-th substep) and arithmetic are those of ``SimWorld.run``, so recordings
simulated with ``SimWorld.run`` and fits made here agree to the last bit.
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Callable, Iterator
from dataclasses import replace

import numpy as np

from voe.gap.effects.base import Effect
from voe.sim.lockstep import run_lockstep
from voe.sim.scenefile import Materials, SceneSpec, SimState, SimWorld

KICK_EVERY = 4e-3  # s, as SimWorld.run

PreparedForce = Callable[[SimState], tuple[np.ndarray, np.ndarray]]


def run(world: SimWorld, times: np.ndarray, substep: float, force: PreparedForce | None = None,
        kick_every: float = KICK_EVERY) -> np.ndarray:
    """Step ``world`` through ``times`` (T,) from ``times[0]``; return poses (T, B, 3).

    Args:
        force: maps the state to (force (B, 2) N, torque (B,) N m); None for the nominal scene.
    """
    return run_lockstep([world], [times], substep, force, kick_every)[0]


def tiled(scene: SceneSpec, n: int) -> SceneSpec:
    """``scene`` with its bodies repeated ``n`` times: what a force law prepared for ``n`` stacked
    windows sees. Without joints the names repeat, so an effect limited to a body acts on that
    body in every copy; with joints each copy's bodies and joints are renamed (``arm#2``), so a
    joint effect finds each copy's joints (``run_many`` then stacks only effects on all bodies)."""
    if n == 1:
        return scene
    if not scene.joints:
        return replace(scene, bodies=scene.bodies * n, joints=())
    bodies = tuple(replace(b, name=f"{b.name}#{k}") for k in range(n) for b in scene.bodies)
    joints = tuple(replace(j, a=f"{j.a}#{k}", b=None if j.b is None else f"{j.b}#{k}")
                   for k in range(n) for j in scene.joints)
    return replace(scene, bodies=bodies, joints=joints)


def stackable(scene: SceneSpec, effect: Effect | None) -> bool:
    """Whether ``effect``'s force law can be prepared for stacked copies of ``scene``: always
    without joints; with joints (renamed copies) only if no force part is limited to named bodies."""
    return effect is None or not scene.joints or all(e.bodies is None for e in effect.parts if e.has_forces)


def run_many(scene: SceneSpec, starts: list[tuple[np.ndarray, np.ndarray]], times: list[np.ndarray], substep: float,
             effect: Effect | None, params: np.ndarray | None, kick_every: float = KICK_EVERY) -> list[np.ndarray]:
    """Simulate several windows of ``scene`` under one effect and parameter vector.

    Args:
        starts: (pose (B, 3), vel (B, 3)) at the start of each window.
        times: (T_i,) sample times of each window.

    Returns:
        Poses (T_i, B, 3) per window, each exactly as ``run`` would give it alone.

    A force part limited to named bodies on a scene with joints cannot be stacked
    (``stackable``); its windows go one at a time.
    """
    with _collector_paused():
        return _run_many(scene, starts, times, substep, effect, params, kick_every,
                         effect.materials(params, scene) if effect is not None else None)


def run_many_recorded(scene: SceneSpec, starts: list[tuple[np.ndarray, np.ndarray]], times: list[np.ndarray],
                      substep: float, effect: Effect | None, params: np.ndarray | None,
                      kick_every: float = KICK_EVERY) -> tuple[list[np.ndarray], list[np.ndarray], Materials | None]:
    """``run_many`` of ``effect`` with its region materials (set per contact) left out, and the
    contacts they would have been set for.

    Returns:
        Poses (T_i, B, 3) per window; per window the contacts (N_i, 3) as ``SimWorld`` records
        them; and the full materials, for ``voe.sim.scenefile.region_inert``: where that holds,
        a window's poses are exactly ``run_many``'s with the region materials.
    """
    mats = effect.materials(params, scene) if effect is not None else None
    bare = replace(mats, region_elasticity=None, region_friction=None) if mats is not None else None
    records: list[list] = [[] for _ in starts]
    with _collector_paused():
        poses = _run_many(scene, starts, times, substep, effect, params, kick_every, bare, records)
    return poses, [np.array(r, dtype=float).reshape(-1, 3) for r in records], mats


@contextlib.contextmanager
def _collector_paused() -> Iterator[None]:
    """Python's cyclic garbage collector off for one batch of rollouts, then back as it was.

    Why: a rollout allocates many short-lived containers (the kicks' lists, pymunk's objects),
    and every 700 of them start a collection of the young objects, now and then of the older
    generations too, over a heap that holds scipy and pandas (the collector was 3.5 % of
    ``bench/gap_speed.py``'s samples). Paused, the garbage is collected at the first allocations
    after the batch. Nothing a rollout computes depends on when garbage is collected.
    """
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _run_many(scene: SceneSpec, starts: list[tuple[np.ndarray, np.ndarray]], times: list[np.ndarray],
              substep: float, effect: Effect | None, params: np.ndarray | None, kick_every: float,
              mats: Materials | None, records: list[list] | None = None) -> list[np.ndarray]:
    """``run_many`` with the worlds built with ``mats`` (the effect's materials, or those without its
    region materials) and, if ``records`` is given, one contact list per window (``SimWorld``'s
    ``contacts``)."""
    worlds = [SimWorld(scene, pose0, vel0, mats, None if records is None else records[i])
              for i, (pose0, vel0) in enumerate(starts)]
    if not worlds:
        return []
    groups = [list(range(len(worlds)))] if stackable(scene, effect) else [[i] for i in range(len(worlds))]
    out: list[np.ndarray] = [np.empty(0)] * len(worlds)
    for g in groups:
        force = effect.prepare(params, tiled(scene, len(g))) if effect is not None else None
        for i, pose in zip(g, run_lockstep([worlds[i] for i in g], [times[i] for i in g], substep, force,
                                           kick_every), strict=True):
            out[i] = pose
    return out
