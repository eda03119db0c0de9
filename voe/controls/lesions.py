"""Lesioned oracles: the physics oracle with exactly one law knocked out.

Why: a probe for a concept is only valid if a model that lacks the corresponding law fails it,
and a model that lacks some *other* law still passes it. Each lesion below is the full physics
oracle (``voe.models.oracle``) with one change, and declares in ``voe.controls.builtin`` which
concepts it should break. Each is calibrated like the intact oracle (noise fitted by maximum
likelihood on ordinary training clips), so its surprise is an honest likelihood.

Lesions:

* ``no-gravity``: re-simulates with gravity switched off.
* ``no-collisions``: objects pass through static geometry and through each other.
* ``forget-occluded``: an object that is out of sight is forgotten; when something comes into
  view it is a new object, drawn from the prior.
* ``no-shape-memory``: shape and size are not remembered (so not behind a screen either): every
  frame's shape and size are scored under the prior of new objects.
* ``no-inertia``: objects tend to stop: each frame is re-simulated from rest.
* ``energy-gain``: bounces may gain energy (restitution above 1).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from voe.io.batch import Batch
from voe.models import statelik as sl
from voe.models.oracle import PhysicsOracle
from voe.sim.scene import Scene
from voe.sim.world import World

LESIONS = ("no-gravity", "no-collisions", "forget-occluded", "no-shape-memory", "no-inertia", "energy-gain")
_SHAPE = [sl.CONT.index("width"), sl.CONT.index("height")]


class LesionedOracle(PhysicsOracle):
    """The physics oracle with one law knocked out (see the module docstring).

    Args:
        lesion: one of ``LESIONS``.
        **kw: the oracle's own arguments (noise, elasticity, friction, substeps, p_visible).
    """

    def __init__(self, lesion: str, **kw: Any) -> None:
        if lesion not in LESIONS:
            from voe.errors import UnknownNameError

            raise UnknownNameError(f"unknown lesion '{lesion}' (known: {', '.join(LESIONS)})")
        if lesion == "energy-gain":
            kw.setdefault("elasticity", 1.6)  # x floor elasticity 0.75-0.9 -> restitution > 1
        super().__init__(**kw)
        self.lesion = lesion
        self.name = f"oracle-{lesion}"

    def config(self) -> dict[str, Any]:
        return {**super().config(), "lesion": self.lesion}

    # -- hooks of PhysicsOracle -------------------------------------------------------------
    def _geometry(self, geo: dict[str, Any]) -> dict[str, Any]:
        if self.lesion == "no-gravity":
            return {**geo, "gravity": [0.0, 0.0]}
        if self.lesion == "no-collisions":
            return {**geo, "statics": []}
        return geo

    def _world(self, scene: Scene, dt: float) -> World:
        if self.lesion == "no-inertia":
            scene = scene.with_bodies(tuple(replace(b, vx=0.0, vy=0.0, omega=0.0) for b in scene.bodies))
        world = World(scene, dt, self.substeps)
        if self.lesion == "no-collisions":
            for slot in world.bodies():
                world.set_passable(slot, statics=True, objects=True, floor=True)
        return world

    def _forget(self, present_t: np.ndarray) -> np.ndarray:
        """Slots whose memory is dropped after frame t: ``(K,)`` bool."""
        if self.lesion == "forget-occluded":
            return ~present_t
        return np.zeros_like(present_t)

    # -- the protocol ----------------------------------------------------------------------------
    def _predict(self, batch: Batch):
        mean, kind, circ, pp = super()._predict(batch)
        if self.lesion == "forget-occluded":
            # what was out of sight is forgotten: anything coming into view is new
            ret = kind == sl.RETURNING
            kind = np.where(ret, sl.NEW, kind).astype(kind.dtype)
            pp = np.where(ret, self.noise.p_present[sl.NEW], pp)
        return mean, kind, circ, pp

    def frame_nll(self, batch: Batch) -> np.ndarray:
        if self.lesion != "no-shape-memory":
            return super().frame_nll(batch)
        mean, kind, circ, pp = self._predict(batch)
        noise = self.noise
        sig, sig_r = np.array(noise.sigma), np.array(noise.sigma_return)
        sig[_SHAPE] = np.array(noise.prior_sigma)[_SHAPE]
        sig_r[_SHAPE] = np.array(noise.prior_sigma)[_SHAPE]
        mean = mean.copy()
        mean[..., _SHAPE] = np.array(noise.prior_mean)[_SHAPE]
        blind = replace(noise, sigma=tuple(sig), sigma_return=tuple(sig_r), p_keep=0.5)
        return sl.score(batch, mean, kind, blind, pp, circ)
