"""Lesioned oracles: the physics oracle with exactly one law knocked out.

Why: a probe for a concept is only valid if a model that lacks the corresponding law fails it,
and a model that lacks some *other* law still passes it. Each lesion is a small class in the
registry ``LESIONS`` (``voe.controls.lesion_registry``) that carries what it changes in the
oracle (a hook or two) *and* what it declares, with a reason, for every registered concept.
There is no default: adding a concept without a declaration from every lesion fails the
conformance test (``tests/controls/test_lesions.py``), so nobody can forget it.

Each lesioned oracle is calibrated like the intact one (noise fitted by maximum likelihood on
ordinary training clips), so its surprise is an honest likelihood.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.controls.lesion_registry import LESIONS, Lesion, get_lesion
from voe.io.batch import Batch
from voe.models.oracle import PhysicsOracle
from voe.sim.scene import Scene
from voe.sim.world import World

__all__ = ["LESIONS", "Lesion", "LesionedOracle"]


class LesionedOracle(PhysicsOracle):
    """The physics oracle with one law knocked out; the lesion supplies the changed hooks.

    Args:
        lesion: a name in ``LESIONS`` (``no-gravity``, ``forget-occluded``, ...).
        **kw: the oracle's own arguments (noise, elasticity, friction, substeps, p_visible).
    """

    def __init__(self, lesion: str, **kw: Any) -> None:
        self.law: Lesion = get_lesion(lesion)
        super().__init__(**self.law.oracle_args(kw))
        self.lesion = self.law.name
        self.name = f"oracle-{self.lesion}"

    def config(self) -> dict[str, Any]:
        return {**super().config(), "lesion": self.lesion}

    # -- hooks of PhysicsOracle, each handed to the lesion ---------------------------------------
    def _geometry(self, geo: dict[str, Any]) -> dict[str, Any]:
        return self.law.geometry(geo)

    def _world(self, scene: Scene, dt: float) -> World:
        world = World(self.law.scene(scene), dt, self.substeps)
        self.law.configure(world)
        return world

    def _forget(self, present_t: np.ndarray) -> np.ndarray:
        """Slots whose memory is dropped after frame t: ``(K,)`` bool."""
        return self.law.forget(present_t)

    def _predict(self, one: Batch, grid=None):
        *pred, log_prior = super()._predict(one, grid)
        return (*self.law.predict(self, *pred), log_prior)

    def _shape_prior(self, kind: np.ndarray) -> np.ndarray | None:
        return self.law.shape_prior(kind)


def lesion_names() -> tuple[str, ...]:
    """Registered lesion names, in registration order."""
    return tuple(LESIONS)
