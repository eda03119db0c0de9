"""Point predictors made into true likelihoods with calibrated Gaussian noise.

Why: a deterministic simulator (constant velocity, a user's point predictor, the physics oracle)
only says where things will be. Adding Gaussian noise whose scale is fitted by maximum likelihood
on possible clips, plus presence and shape probabilities (see ``voe.models.statelik``), turns it
into a normalised density over the state observation, so its surprise is comparable to any
other model's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict
from typing import Any

import numpy as np

from voe.io.batch import Batch
from voe.models import statelik as sl

#: ``step(states (N, F), dt, feature_names) -> (N, F)``: advance states by one frame.
Step = Callable[[np.ndarray, float, tuple[str, ...]], np.ndarray]


def _constant_velocity(s: np.ndarray, dt: float, names: tuple[str, ...]) -> np.ndarray:
    return sl.constant_velocity_step(s, dt, names)


class PointPredictorAdapter:
    """Wrap a one-frame point predictor ``step`` into a state model with calibrated noise.

    Args:
        step: ``step(states (N, F), dt, feature_names) -> (N, F)``.
        noise: calibrated ``Noise`` fields (from ``calibrate``); defaults are rough guesses.
        name: model name.

    Usage::

        model = PointPredictorAdapter(my_step)
        model.calibrate(heldout_possible_batch)   # fits the noise by maximum likelihood
        model.frame_nll(batch)
    """

    observation = "states"

    def __init__(self, step: Step, noise: dict[str, Any] | sl.Noise | None = None,
                 name: str = "point") -> None:
        self.step, self.name = step, name
        if isinstance(noise, dict):
            noise = sl.Noise(**{k: tuple(v) if isinstance(v, list) else v for k, v in noise.items()})
        self.noise = noise or sl.Noise()

    # -- the protocol ---------------------------------------------------------------------
    def frame_nll(self, batch: Batch) -> np.ndarray:
        mean, kind, circ, pp = self._predict(batch)
        return sl.score(batch, mean, kind, self.noise, pp, circ)

    # -- calibration --------------------------------------------------------------------------
    def calibrate(self, batch: Batch) -> sl.Noise:
        """Fit the noise on possible clips by maximum likelihood; returns and keeps it."""
        mean, kind, circ, _ = self._predict(batch)
        self.noise = sl.fit_noise(batch, mean, kind, circ)
        return self.noise

    def config(self) -> dict[str, Any]:
        return {"noise": asdict(self.noise)}

    # -- internals ------------------------------------------------------------------------------
    def _advance(self, mem: np.ndarray, batch: Batch) -> np.ndarray:
        """Predicted state at t from memory at t-1 for every (b, t, k): ``(B, T, K, F)``."""
        B, T, K, F = mem.shape
        out = np.full_like(mem, np.nan)
        prev = mem[:, :-1].reshape(-1, F)
        ok = ~np.isnan(prev[:, 0])
        flat = np.full_like(prev, np.nan)
        if ok.any():
            flat[ok] = self.step(prev[ok], batch.dt, batch.feature_names)
        out[:, 1:] = flat.reshape(B, T - 1, K, F)
        return out

    def _predict(self, batch: Batch):
        names = batch.feature_names
        sl.cont_index(names)
        states = batch.states.astype(np.float64)
        mem, known, _ = sl.carry(states, batch.present, batch.dt, lambda s, dt: self.step(s, dt, names))
        pred = self._advance(mem, batch)  # (B, T, K, F)
        kind = sl.slot_kind(known, batch.present)
        circ = np.zeros(kind.shape, dtype=bool)
        circ[:, 1:] = mem[:, :-1, :, names.index("is_circle")] > 0.5
        return pred[..., sl.cont_index(names)], kind, circ, None
