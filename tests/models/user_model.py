"""User models for the tests: one that keeps the protocol and several that break it."""

from __future__ import annotations

import numpy as np


class Thing:
    """A well-behaved user model: surprise is the number of present objects (frame 0 warm-up)."""

    observation = "states"

    def __init__(self, scale: float = 1.0) -> None:
        self.name = "thing"
        self.scale = float(scale)

    def frame_nll(self, batch):
        out = self.scale * batch.present.sum(-1).astype(float)  # (B, T)
        out[:, 0] = np.nan
        return out


class WrongShape(Thing):
    def frame_nll(self, batch):
        return np.zeros(batch.shape[1])  # (T,) instead of (B, T)


class NaNInside(Thing):
    def frame_nll(self, batch):
        out = super().frame_nll(batch)
        out[0, 5] = np.nan
        return out


class BatchDependent(Thing):
    def frame_nll(self, batch):
        return np.full(batch.shape, float(len(batch)))


def make_thing(scale: float = 2.0) -> Thing:
    """A factory instead of a class."""
    return Thing(scale)
