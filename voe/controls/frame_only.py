"""Frame-only scorers: the surprise of a frame depends on that frame alone.

Why: on a spliced quadruplet the impossible pair holds exactly the frames of the possible pair,
so *any* function of single frames gives the two pairs the same summed surprise: such a scorer
must land at exactly chance (every set a tie, accuracy 0.5). Running a few of them over a probe
set is an empirical proof of frame balance; on concepts that use the pair fallback it measures
how much a single frame gives away.

Both scorers follow the model protocol (``frame_nll(batch) -> (B, T)``).
"""

from __future__ import annotations

import hashlib

import numpy as np

from voe.io.batch import Batch


class PixelDensity:
    """A per-frame image density: independent per-pixel Bernoulli over binarised pixels.

    The probabilities are fitted by maximum likelihood on frames (with add-one smoothing), so the
    surprise is a true ``-log p(frame)`` that ignores every other frame of the clip.

    Args:
        threshold: a pixel is "on" when its intensity is above this (0-255).
        probs: optional fitted ``(H, W)`` on-probabilities; without them, ``fit`` must be called.
    """

    observation = "frames"

    def __init__(self, threshold: int = 40, probs: np.ndarray | None = None) -> None:
        self.name = "frame-only-density"
        self.threshold = int(threshold)
        self.probs = probs

    def fit(self, frames: np.ndarray) -> PixelDensity:
        """Fit on ``(N, H, W)`` or ``(B, T, H, W)`` frames; returns self."""
        on = (frames.reshape((-1,) + frames.shape[-2:]) > self.threshold)  # (N, H, W)
        self.probs = (on.sum(0) + 1.0) / (on.shape[0] + 2.0)
        return self

    def frame_nll(self, batch: Batch) -> np.ndarray:
        if self.probs is None:  # fit on the batch itself: still a function of single frames
            self.fit(batch.frames)
        on = batch.frames > self.threshold  # (B, T, H, W)
        logp = np.where(on, np.log(self.probs), np.log1p(-self.probs))  # (B, T, H, W)
        return -logp.sum(axis=(2, 3))  # (B, T)


class RandomFeatureScorer:
    """An arbitrary fixed function of the pixels: a random projection followed by a nonlinearity.

    It is not a likelihood; it stands for "any single-frame statistic" a model might latch onto.
    Different seeds give different functions.
    """

    observation = "frames"

    def __init__(self, seed: int = 0, n_features: int = 16) -> None:
        self.name = f"frame-only-random-{seed}"
        self.seed, self.n_features = int(seed), int(n_features)
        self._proj: dict[tuple[int, int], np.ndarray] = {}

    def _projection(self, h: int, w: int) -> np.ndarray:
        if (h, w) not in self._proj:
            digest = hashlib.sha256(f"{self.seed}:{h}x{w}".encode()).digest()
            rng = np.random.default_rng(int.from_bytes(digest[:8], "little"))
            self._proj[(h, w)] = rng.normal(0, 1 / np.sqrt(h * w), (h * w, self.n_features))
        return self._proj[(h, w)]

    def frame_nll(self, batch: Batch) -> np.ndarray:
        B, T, H, W = batch.frames.shape
        x = batch.frames.reshape(B * T, H * W).astype(np.float64) / 255.0  # (B*T, H*W)
        z = np.tanh(x @ self._projection(H, W))  # (B*T, n_features)
        return (z**2).sum(-1).reshape(B, T) + np.abs(z).max(-1).reshape(B, T)  # (B, T)
