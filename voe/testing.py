"""Fake models that tests and users can lean on (like lm-evaluation-harness's dummy model).

* ``BlindModel``: the same surprise for every frame: every comparison is a tie (accuracy 0.5).
* ``RandomModel``: seeded noise per clip id: a chance-level scorer.
* ``CheatingModel``: reads the clip id's variant (``AB``, ``BA``, ``impossible``) and is more
  surprised after the onset of impossible clips: a perfect scorer, for testing metrics end to end.
* ``PixelSumModel``: a frame-only scorer (surprise depends on that frame alone).
"""

from __future__ import annotations

import hashlib

import numpy as np

from voe.io.batch import Batch

_IMPOSSIBLE_VARIANTS = ("AB", "BA", "impossible")


def _clip_rng(clip_id: str, seed: int) -> np.random.Generator:
    digest = hashlib.sha256(f"{seed}:{clip_id}".encode()).digest()
    return np.random.default_rng(int.from_bytes(digest[:8], "little"))


class BlindModel:
    """Constant surprise ``value`` nats for every frame after ``warmup``."""

    observation = "frames"

    def __init__(self, value: float = 1.0, warmup: int = 1) -> None:
        self.name = "blind"
        self.value, self.warmup = float(value), int(warmup)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        out = np.full(batch.shape, self.value)  # (B, T)
        out[:, : self.warmup] = np.nan
        return out


class RandomModel:
    """Surprise drawn from a clip-seeded exponential: deterministic, batch-invariant, chance-level."""

    observation = "states"

    def __init__(self, seed: int = 0) -> None:
        self.name = f"random-{seed}"
        self.seed = int(seed)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        B, T = batch.shape
        ids = batch.clip_ids or tuple(str(i) for i in range(B))
        return np.stack([_clip_rng(c, self.seed).exponential(1.0, T) for c in ids])  # (B, T)


class CheatingModel:
    """More surprised after the onset of clips whose id names an impossible variant."""

    observation = "frames"

    def __init__(self, onset: int = 0, jump: float = 5.0) -> None:
        self.name = "cheating"
        self.onset, self.jump = int(onset), float(jump)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        out = np.ones(batch.shape)  # (B, T)
        for b, cid in enumerate(batch.clip_ids):
            if cid.rsplit("-", 1)[-1] in _IMPOSSIBLE_VARIANTS:
                out[b, self.onset:] += self.jump
        return out


class PixelSumModel:
    """A frame-only scorer: surprise is a fixed function of the current frame's pixels alone."""

    observation = "frames"

    def __init__(self, scale: float = 1e-4) -> None:
        self.name = "pixel-sum"
        self.scale = float(scale)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        f = batch.frames.astype(np.float64)  # (B, T, H, W)
        return self.scale * (f ** 2).sum(axis=(2, 3))  # (B, T)
