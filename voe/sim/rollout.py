"""Run a ``World`` for a clip and record frames, states and visibility.

Why: every probe and training clip is the same record (frames, states, present, geometry); this
module is the single place that turns a stepping world into that record, so concepts only decide
*what happens*, never how it is observed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from voe.sim.render import Renderer
from voe.sim.scene import Scene, SimConfig
from voe.sim.world import World


@dataclass
class Recording:
    """Observations of one clip.

    Attributes:
        frames: ``(T, H, W)`` uint8.
        states: ``(T, K, F)`` float32; NaN where the slot is not present.
        present: ``(T, K)`` bool; the object exists, is in the window and is not fully occluded.
        exists: ``(T, K)`` bool; the object exists (ground truth, visible or not).
        geometry: JSON-able static geometry and occluders (``Scene.geometry()``).
    """

    frames: np.ndarray
    states: np.ndarray
    present: np.ndarray
    exists: np.ndarray
    geometry: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return int(self.frames.shape[0])


def visible_slots(world: World, scene: Scene, pixel: float = 0.0) -> dict[int, bool]:
    """Which live slots are visible: inside the window and not fully behind a screen.

    An object within ``pixel`` of a screen's edge counts as visible: anti-aliasing shows it.
    """
    out = {}
    w, h = scene.extent
    for slot, (lo, hi) in world.bboxes().items():
        inside = hi[0] > pixel and lo[0] < w - pixel and hi[1] > pixel and lo[1] < h - pixel
        hidden = any(o.contains_box(lo, hi, pixel) for o in scene.occluders)
        out[slot] = inside and not hidden
    return out


class Recorder:
    """Accumulates frames from a world, one ``capture`` per frame.

    Args:
        scene: the clip's scene (for geometry and occluders).
        cfg: time/image settings.
    """

    def __init__(self, scene: Scene, cfg: SimConfig, renderer: Renderer | None = None) -> None:
        self.scene, self.cfg = scene, cfg
        self.renderer = renderer or Renderer(scene.statics, scene.occluders, scene.extent, cfg.size)
        self.frames: list[np.ndarray] = []
        self.states: list[np.ndarray] = []
        self.present: list[np.ndarray] = []
        self.exists: list[np.ndarray] = []

    def capture(self, world: World) -> None:
        """Record the world as it is now."""
        k = self.cfg.n_slots
        st = world.observe(k)  # (K, F)
        vis = visible_slots(world, self.scene, self.renderer.pix)
        present = np.zeros(k, dtype=bool)
        exists = np.zeros(k, dtype=bool)
        objs = []
        for slot, spec in world.specs().items():
            b = world.body(slot)
            exists[slot] = True
            present[slot] = vis[slot]
            objs.append((spec, b.position.x, b.position.y, b.angle))
        objs.sort(key=lambda o: o[0].slot)  # draw order = slot order, deterministic
        st[~present] = np.nan
        self.frames.append(self.renderer.frame(objs))
        self.states.append(st)
        self.present.append(present)
        self.exists.append(exists)

    def result(self) -> Recording:
        return Recording(
            frames=np.stack(self.frames), states=np.stack(self.states),
            present=np.stack(self.present), exists=np.stack(self.exists),
            geometry=self.scene.geometry(),
        )


def simulate(scene: Scene, cfg: SimConfig,
             events: dict[int, Callable[[World], None]] | None = None,
             world: World | None = None, start: int = 0) -> Recording:
    """Simulate ``cfg.n_frames`` frames (from frame ``start`` of an existing world if given).

    ``events[t]`` is called on the world just before frame ``t`` is captured; concepts use it
    for law-breaking edits at the onset and for counterfactual worlds.
    """
    events = events or {}
    world = world or World(scene, cfg.dt, cfg.substeps)
    rec = Recorder(scene, cfg)
    for t in range(start, cfg.n_frames):
        if t > start:
            world.step()
        if t in events:
            events[t](world)
        rec.capture(world)
    return rec.result()
