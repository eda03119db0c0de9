"""A user model that takes its time, so that a scoring run can be interrupted partway."""

from __future__ import annotations

import time

import numpy as np


class Slow:
    """Surprise = number of present objects; sleeps ``delay`` seconds per batch."""

    observation = "states"

    def __init__(self, delay: float = 0.0) -> None:
        self.name = "slow"
        self.delay = float(delay)

    def frame_nll(self, batch):
        time.sleep(self.delay)
        out = batch.present.sum(-1).astype(float)  # (B, T)
        out[:, 0] = np.nan
        return out
