"""Lesioned oracles: the physics oracle with exactly one law knocked out.

Why: a probe for a concept is only valid if a model that lacks the corresponding law fails it,
and a model that lacks some *other* law still passes it. Each lesion below is the full physics
oracle (``voe.models.oracle``) with one change, and declares in ``voe.controls.builtin`` which
concepts it should break. Each is calibrated like the intact oracle (noise fitted by maximum
likelihood on ordinary training clips), so its surprise is an honest likelihood.

Lesions:

* ``no-gravity``: re-simulates with gravity switched off.
* ``no-collisions``: objects pass through each other and through walls, shelves and ramps (the
  issue's "objects and walls are passable"); the floor still holds them, as in the pass-through
  counterfactual world.
* ``forget-occluded``: an object that is out of sight is forgotten; when something comes into
  view it is a new object, drawn from the prior.
* ``no-shape-memory``: shape and size are not remembered behind a screen: an object that comes
  back into view has its shape and size scored under the prior of new objects, and its
  reappearance is expected at the generic rate, not when its (forgotten) edges clear the screen.
* ``no-inertia``: objects tend to stop: each frame is re-simulated from rest.
* ``energy-gain``: bounces may gain energy: the oracle's elasticity hypotheses run up to 1.8, so a
  restitution above 1 is as likely a priori as an ordinary one.
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
#: Elasticity hypotheses of ``energy-gain``: the intact grid continued up to 1.8, so that
#: restitutions above 1 (a bounce higher than the drop) are as likely a priori as ordinary ones.
ENERGY_GAIN_GRID = tuple(round(0.1 + 0.05 * i, 2) for i in range(35))


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
            kw.setdefault("elasticity", ENERGY_GAIN_GRID)
        super().__init__(**kw)
        self.lesion = lesion
        self.name = f"oracle-{lesion}"

    def config(self) -> dict[str, Any]:
        return {**super().config(), "lesion": self.lesion}

    # -- hooks of PhysicsOracle -------------------------------------------------------------
    def _geometry(self, geo: dict[str, Any]) -> dict[str, Any]:
        if self.lesion == "no-gravity":
            return {**geo, "gravity": [0.0, 0.0]}
        return geo

    def _world(self, scene: Scene, dt: float) -> World:
        if self.lesion == "no-inertia":
            scene = scene.with_bodies(tuple(replace(b, vx=0.0, vy=0.0, omega=0.0) for b in scene.bodies))
        world = World(scene, dt, self.substeps)
        if self.lesion == "no-collisions":
            for slot in world.bodies():
                world.set_passable(slot, statics=True, objects=True, floor=False)
        return world

    def _forget(self, present_t: np.ndarray) -> np.ndarray:
        """Slots whose memory is dropped after frame t: ``(K,)`` bool."""
        if self.lesion == "forget-occluded":
            return ~present_t
        return np.zeros_like(present_t)

    # -- the protocol ----------------------------------------------------------------------------
    def _predict(self, batch: Batch):
        mean, kind, circ, pp, contact = super()._predict(batch)
        ret = kind == sl.RETURNING
        if self.lesion == "forget-occluded":
            # what was out of sight is forgotten: anything coming into view is new
            kind = np.where(ret, sl.NEW, kind).astype(kind.dtype)
            pp = np.where(ret[:, None], self.noise.p_present[sl.NEW], pp)
        if self.lesion == "no-shape-memory":
            # where a hidden object's edges are is not remembered, so neither is when it will
            # show again: reappearing gets the generic rate, not the screen's geometry
            pp = np.where(ret[:, None], self.noise.p_present[sl.RETURNING], pp)
        return mean, kind, circ, pp, contact

    def _shape_prior(self, kind: np.ndarray) -> np.ndarray | None:
        if self.lesion == "no-shape-memory":
            return kind == sl.RETURNING  # what comes back from behind a screen has a fresh look
        return None
