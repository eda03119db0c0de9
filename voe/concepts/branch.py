"""Branch one rollout into a possible and an impossible continuation (the pair fallback).

Why: the pair concepts (solidity, gravity, collision, energy) all do the same three things:
roll the possible clip out while keeping the true states (a ``Recording`` has NaN where an object
is hidden, but the onset of an occluded violation must be found from where the object really is),
replay the same scene with a law-breaking edit at one frame, and take as onset the first frame
whose true state differs. Replaying the same scene in the same process is deterministic, so every
frame before the onset is byte-identical in the two clips; ``rollout`` checks nothing itself,
``first_difference`` and the concept tests do.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.errors import ConceptError
from voe.sim.rollout import Recorder, Recording
from voe.sim.scene import Scene, SimConfig
from voe.sim.world import World

#: ``hook(t, world)`` runs on the world just before frame ``t`` is captured.
Hook = Callable[[int, World], None]


def rollout(scene: Scene, cfg: SimConfig, hook: Hook | None = None) -> tuple[Recording, np.ndarray]:
    """Simulate a clip; return it with the true states ``(T, K, F)`` (not NaN when hidden)."""
    world = World(scene, cfg.dt, cfg.substeps)
    rec = Recorder(scene, cfg)
    for t in range(cfg.n_frames):
        if t > 0:
            world.step()
        if hook is not None:
            hook(t, world)
        rec.capture(world)
    return rec.result(), rec.truth()  # (T, K, F)


def edited(at: int, edit: Callable[[World], None], after: Hook | None = None) -> Hook:
    """A hook that applies ``edit`` at frame ``at`` and then ``after`` on every later frame."""

    def hook(t: int, world: World) -> None:
        if t == at:
            edit(world)
        elif t > at and after is not None:
            after(t, world)

    return hook


def first_difference(a: np.ndarray, b: np.ndarray, tol: float = 0.0) -> int:
    """First frame where two ``(T, ...)`` state arrays differ by more than ``tol`` (NaN == NaN).

    Returns ``T`` when they never differ.
    """
    diff = np.abs(a - b)
    differs = (diff > tol) | (np.isnan(a) != np.isnan(b))
    per_frame = differs.reshape(len(a), -1).any(axis=1)
    return int(np.argmax(per_frame)) if per_frame.any() else len(a)


def pair(scene: Scene, cfg: SimConfig, hook: Hook, what: str,
         possible: tuple[Recording, np.ndarray] | None = None) -> tuple[Recording, Recording, int]:
    """Possible clip, impossible clip (``hook`` applied) and the onset (first differing true state).

    Args:
        possible: the possible clip's ``rollout`` if the caller already has it.

    Raises:
        ConceptError: the edit changed nothing, or a frame before the onset differs.
    """
    pos, truth_pos = possible if possible is not None else rollout(scene, cfg)
    imp, truth_imp = rollout(scene, cfg, hook)
    onset = first_difference(truth_pos, truth_imp)
    if onset >= cfg.n_frames:
        raise ConceptError(f"{what}: the violation changed nothing; widen the clip or move the event")
    if not (np.array_equal(pos.frames[:onset], imp.frames[:onset])
            and np.array_equal(pos.present[:onset], imp.present[:onset])):
        raise ConceptError(f"{what}: frames before the onset {onset} differ; the replay is not deterministic")
    return pos, imp, onset
