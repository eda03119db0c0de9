"""Physics oracle: re-simulate every frame in pymunk from the observed state, plus calibrated noise.

Why: it is the upper bound a learned state model can approach. For each frame it rebuilds the
clip's static segments and screens from ``batch.geometry``, places every known object at its last
observed state (or its carried state while hidden), steps one frame and predicts the next state.
Presence is predicted from the same geometry: an object whose predicted box is outside the window
or fully behind a screen should be absent (probability ``1 - p_visible``), any other known object
present. Noise is fitted by maximum likelihood like the other point predictors. Mass, friction
and elasticity are not observed; ``elasticity`` and ``friction`` are model arguments.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.errors import ModelContractError
from voe.io.batch import Batch
from voe.models import statelik as sl
from voe.models.point import PointPredictorAdapter
from voe.sim.rollout import visible_slots
from voe.sim.scene import Body, Scene, geometry_from_dict
from voe.sim.world import World


class PhysicsOracle(PointPredictorAdapter):
    """Reference upper bound (see the module docstring)."""

    def __init__(self, noise: dict[str, Any] | None = None, elasticity: float = 0.5,
                 friction: float = 0.0, substeps: int = 10, p_visible: float = 0.99) -> None:
        super().__init__(lambda s, dt, n: s, noise, name="oracle")
        self.elasticity, self.friction = float(elasticity), float(friction)
        self.substeps, self.p_visible = int(substeps), float(p_visible)

    def config(self) -> dict[str, Any]:
        return {**super().config(), "elasticity": self.elasticity, "friction": self.friction,
                "substeps": self.substeps, "p_visible": self.p_visible}

    def _body(self, slot: int, s: np.ndarray, ix: dict[str, int]) -> Body:
        circle = s[ix["is_circle"]] > 0.5
        w, h = max(float(s[ix["width"]]), 0.05), max(float(s[ix["height"]]), 0.05)
        return Body(slot=slot, shape="circle" if circle else "box", width=w, height=h if not circle else w,
                    x=float(s[ix["x"]]), y=float(s[ix["y"]]), angle=float(s[ix["angle"]]),
                    vx=float(s[ix["vx"]]), vy=float(s[ix["vy"]]), omega=float(s[ix["omega"]]),
                    friction=self.friction, elasticity=self.elasticity,
                    intensity=float(s[ix["intensity"]]))

    def _clip(self, states: np.ndarray, present: np.ndarray, geo: dict[str, Any], dt: float,
              names: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
        """Predictions ``(T, K, F)`` (NaN for unknown slots) and P(present) ``(T, K)``."""
        T, K, F = states.shape
        ix = {n: i for i, n in enumerate(names)}
        geo = self._geometry(geo)
        statics, occluders = geometry_from_dict(geo)
        gravity = tuple(geo.get("gravity", (0.0, -9.81)))
        extent = tuple(geo.get("extent", (10.0, 10.0)))
        pred = np.full((T, K, F), np.nan)
        pvis = np.full((T, K), np.nan)
        cur = np.full((K, F), np.nan)
        for t in range(T - 1):
            cur[present[t]] = states[t][present[t]]
            known = [k for k in range(K) if not np.isnan(cur[k, 0])]
            if not known:
                continue
            scene = Scene(tuple(self._body(k, cur[k], ix) for k in known), statics, occluders,
                          gravity, extent)
            world = self._world(scene, dt)
            world.step()
            nxt = world.observe(K).astype(np.float64)
            vis = visible_slots(world, scene)
            for k in known:
                cur[k] = nxt[k]
                pvis[t + 1, k] = self.p_visible if vis[k] else 1 - self.p_visible
            pred[t + 1] = cur
            cur[self._forget(present[t + 1])] = np.nan
        return pred, pvis

    # -- hooks for lesioned variants (voe.controls.lesions) ---------------------------------
    def _geometry(self, geo: dict[str, Any]) -> dict[str, Any]:
        """The clip geometry the oracle simulates in (a lesion may drop gravity or statics)."""
        return geo

    def _world(self, scene: Scene, dt: float) -> World:
        """The world that predicts one frame ahead (a lesion may change its laws)."""
        return World(scene, dt, self.substeps)

    def _forget(self, present_t: np.ndarray) -> np.ndarray:
        """Slots whose memory is dropped after frame t, ``(K,)`` bool: none for the intact oracle."""
        return np.zeros_like(present_t)

    def _predict(self, batch: Batch):
        if len(batch.geometry) != len(batch):
            raise ModelContractError("oracle needs batch.geometry (static segments and screens) per clip")
        names = batch.feature_names
        idx = sl.cont_index(names)
        states = batch.states.astype(np.float64)
        out = [self._clip(states[b], batch.present[b], batch.geometry[b], batch.dt, names)
               for b in range(len(batch))]
        pred = np.stack([o[0] for o in out])  # (B, T, K, F)
        pvis = np.stack([o[1] for o in out])  # (B, T, K)
        known = np.zeros(batch.present.shape, dtype=bool)
        known[:, 1:] = ~np.isnan(pred[:, 1:, :, 0])
        kind = sl.slot_kind(np.cumsum(batch.present, axis=1) > 0, batch.present)
        pp = np.where(kind == sl.NEW, self.noise.p_present[sl.NEW], pvis)
        circ = np.zeros(kind.shape, dtype=bool)
        circ[:, 1:] = pred[:, 1:, :, names.index("is_circle")] > 0.5
        return pred[..., idx], kind, circ, pp
