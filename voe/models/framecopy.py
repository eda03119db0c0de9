"""Frame copy with a calibrated pixel-flip probability: the pixel models' reference.

Observation space: the binarised frame ``frames >= threshold`` (H x W bits; objects are drawn at
intensity >= 0.6, i.e. >= 153 of 255, so they survive binarisation, screens at 64 do not). The
model predicts that every bit equals the previous frame's, flipping independently with probability
``eps``, so ``-log p = n_same * -log(1 - eps) + n_flip * -log(eps)``: a normalised distribution over
the 2^(H W) binary frames. ``eps`` is fitted by maximum likelihood (the fraction of flipped bits
on a training set) by ``voe train framecopy --data DIR``. Frame 0 is not scored.
"""

from __future__ import annotations

import numpy as np

from voe.io.batch import Batch

THRESHOLD = 128


def binarise(frames: np.ndarray, threshold: int = THRESHOLD) -> np.ndarray:
    """``(..., H, W)`` uint8 -> bool bits, the pixel models' observation."""
    return frames >= threshold


class FrameCopy:
    """Reference pixel model (see the module docstring)."""

    observation = "frames"

    def __init__(self, eps: float = 0.002, threshold: int = THRESHOLD) -> None:
        self.name = "framecopy"
        self.eps, self.threshold = float(eps), int(threshold)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        bits = binarise(batch.frames, self.threshold)  # (B, T, H, W)
        flips = (bits[:, 1:] != bits[:, :-1]).sum(axis=(2, 3)).astype(np.float64)  # (B, T-1)
        n = bits.shape[2] * bits.shape[3]
        out = np.full(batch.shape, np.nan)
        out[:, 1:] = -(n - flips) * np.log1p(-self.eps) - flips * np.log(self.eps)
        return out

    def calibrate(self, batch: Batch) -> float:
        """Fit ``eps`` by maximum likelihood on a training batch; returns and keeps it."""
        bits = binarise(batch.frames, self.threshold)
        flips = (bits[:, 1:] != bits[:, :-1]).sum()
        self.eps = float(np.clip((flips + 1) / (bits[:, 1:].size + 2), 1e-6, 0.5))
        return self.eps

    def config(self) -> dict[str, float]:
        return {"eps": self.eps, "threshold": self.threshold}
