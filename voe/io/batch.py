"""The batch a model is scored on: exactly the arrays stored in a probe set.

Why: it sits in ``io`` (not ``models``) because the probe-set reader builds it and must not
depend on the model layer; ``voe.models.protocol`` re-exports it for users.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Batch:
    """Observations of B clips.

    Attributes:
        frames: ``(B, T, H, W)`` uint8 grayscale frames.
        states: ``(B, T, K, F)`` float32 object states; NaN where a slot is not present.
        present: ``(B, T, K)`` bool; the object is visible in that frame.
        feature_names: names of the F state features (``x, y, angle, vx, vy, omega, ...``).
        dt: seconds between frames.
        geometry: per clip, the static segments and occluders (JSON-able dicts); models that
            re-simulate (the physics oracle) need them, others may ignore them.
        clip_ids: opaque keys of the clips (``voe.io.clipkey.clip_key``), for error messages and
            caching only. They name no role, and a model's surprise must not depend on them:
            ``check_model`` renames them and expects the same numbers.
        seeds: per clip, a seed for stochastic scorers (noise draws, diffusion timesteps). Every
            clip of one matched set gets the same seed (common random numbers), so the noise
            cancels in the comparison; a deterministic model ignores it.
    """

    frames: np.ndarray
    states: np.ndarray
    present: np.ndarray
    feature_names: tuple[str, ...]
    dt: float
    geometry: tuple[dict[str, Any], ...] = field(default=())
    clip_ids: tuple[str, ...] = field(default=())
    seeds: tuple[int, ...] = field(default=())

    def __len__(self) -> int:
        return int(self.frames.shape[0])

    @property
    def shape(self) -> tuple[int, int]:
        """``(B, T)``, the shape every ``frame_nll`` must return."""
        return int(self.frames.shape[0]), int(self.frames.shape[1])

    def feature(self, name: str) -> int:
        """Index of a state feature by name."""
        return self.feature_names.index(name)

    def take(self, idx: np.ndarray | list[int] | slice) -> Batch:
        """A sub-batch (rows ``idx``)."""
        if isinstance(idx, slice):
            rows = list(range(len(self)))[idx]
        else:
            rows = [int(i) for i in idx]
        return Batch(self.frames[rows], self.states[rows], self.present[rows], self.feature_names,
                     self.dt, tuple(self.geometry[i] for i in rows) if self.geometry else (),
                     tuple(self.clip_ids[i] for i in rows) if self.clip_ids else (),
                     tuple(self.seeds[i] for i in rows) if self.seeds else ())
