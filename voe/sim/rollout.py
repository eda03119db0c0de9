"""Run a ``World`` for a clip and record frames, states and visibility.

Why: every probe and training clip is the same record (frames, states, present, geometry); this
module is the single place that turns a stepping world into that record, so concepts only decide
*what happens*, never how it is observed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from voe.sim.render import Renderer, renderer_cached, visible
from voe.sim.scene import Scene, SimConfig
from voe.sim.world import Looks, World, decode_poses, new_buffer


class Recording:
    """Observations of one clip.

    Attributes:
        frames: ``(T, H, W)`` uint8; drawn from the states on first access when the recording
            was made by a ``Recorder`` (a rollout that is only compared, never stored, such as a
            concept's ghost run, is then never drawn).
        states: ``(T, K, F)`` float32; NaN where the slot is not present.
        present: ``(T, K)`` bool; the object exists, is in the window and is not fully occluded.
        exists: ``(T, K)`` bool; the object exists (ground truth, visible or not).
        geometry: JSON-able static geometry and occluders (``Scene.geometry()``).
    """

    def __init__(self, frames: np.ndarray | None, states: np.ndarray, present: np.ndarray,
                 exists: np.ndarray, geometry: dict[str, Any] | None = None,
                 draw: Callable[[], np.ndarray] | None = None) -> None:
        if frames is None and draw is None:
            raise ValueError("a Recording needs frames or a way to draw them")
        self._frames, self._draw = frames, draw
        self.states, self.present, self.exists = states, present, exists
        self.geometry = geometry if geometry is not None else {}

    @property
    def frames(self) -> np.ndarray:
        if self._frames is None:
            self._frames, self._draw = self._draw(), None
        return self._frames

    def __len__(self) -> int:
        return int(self.states.shape[0])


def visible_slots(world: World, scene: Scene, pixel: float = 0.0) -> dict[int, bool]:
    """Which live slots are visible: inside the window and not fully behind a screen.

    An object within ``pixel`` of a screen's edge counts as visible: anti-aliasing shows it.
    """
    slots = sorted(world.bodies())
    truth = world.poses(max(slots, default=-1) + 1)  # (K, F) float64
    vis = visible(truth, scene.occluders, scene.extent, pixel)
    return {k: bool(vis[k]) for k in slots}


class Recorder:
    """Accumulates the true state of a world, one ``capture`` per frame; renders on ``result``.

    Args:
        scene: the clip's scene (for geometry and occluders).
        cfg: time/image settings.
        renderer: draws the frames (default: grayscale at ``cfg.size`` for the scene's geometry).
    """

    def __init__(self, scene: Scene, cfg: SimConfig, renderer: Renderer | None = None) -> None:
        self.scene, self.cfg = scene, cfg
        self.geometry = scene.geometry()
        self.renderer = renderer or renderer_cached(scene.statics, scene.occluders, scene.extent, cfg.size)
        self._buf = new_buffer()  # raw pose reads, appended once per frame
        self._frames: list[tuple[int, Looks]] = []  # per frame: bodies read so far, their looks

    def capture(self, world: World) -> None:
        """Record the world as it is now (one batched read; decoded in ``truth``/``result``)."""
        looks = world.read_poses(self._buf)
        self._frames.append((len(self._buf.int_buf()) // 8, looks))

    def _truth(self) -> np.ndarray:
        return decode_poses(self._buf, self._frames, self.cfg.n_slots)  # (T, K, F) float64

    def truth(self) -> np.ndarray:
        """True states so far ``(T, K, F)`` float32, also where an object is hidden (NaN if absent)."""
        return self._truth().astype(np.float32)

    def result(self) -> Recording:
        truth = self._truth()  # (T, K, F) float64
        exists = ~np.isnan(truth[..., 0])  # (T, K)
        present = visible(truth, self.scene.occluders, self.scene.extent, self.renderer.pix)
        states = truth.astype(np.float32)
        states[~present] = np.nan
        renderer = self.renderer
        return Recording(None, states, present, exists, self.geometry,
                         draw=lambda: renderer.clip(states, present))


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
