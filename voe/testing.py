"""Fake models that tests and users can lean on (like lm-evaluation-harness's dummy model).

Honest fakes:

* ``BlindModel``: the same surprise for every frame: every comparison is a tie (accuracy 0.5).
* ``RandomModel``: noise seeded by the clip's content: a chance-level scorer.
* ``PixelSumModel``: a frame-only scorer (surprise depends on that frame alone).
* ``NoisyModel``: a stochastic scorer (``surprise_kind="bound"``) whose noise is drawn from
  ``batch.seeds``; with common random numbers every clip of a set draws the same noise.
* ``CheatingModel``: is *given* the answer key (the probe set's index) and is more surprised
  after the onset of impossible clips: a perfect scorer, for testing metrics end to end.

Cheaters that the blind harness must defeat (``check_model`` rejects each by name; scored
without the check they sit at chance, since keys are opaque and the order is shuffled):

* ``IdReaderModel`` reads ``batch.clip_ids``: a role suffix (``-AB``, ``-impossible``) if there is
  one, otherwise a hash of the id.
* ``PositionModel`` uses the clip's position in the batch.
* ``FuturePeekingModel`` scores every frame by the motion of the whole clip, future included.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from voe.io.batch import Batch

_IMPOSSIBLE_VARIANTS = ("AB", "BA", "impossible")


def _rng(text: str | bytes, seed: int) -> np.random.Generator:
    data = text.encode() if isinstance(text, str) else text
    digest = hashlib.sha256(f"{seed}:".encode() + data).digest()
    return np.random.default_rng(int.from_bytes(digest[:8], "little"))


def _warm(out: np.ndarray, warmup: int = 1) -> np.ndarray:
    out[:, :warmup] = np.nan
    return out


class BlindModel:
    """Constant surprise ``value`` nats for every frame after ``warmup``."""

    observation = "frames"

    def __init__(self, value: float = 1.0, warmup: int = 1) -> None:
        self.name = "blind"
        self.value, self.warmup = float(value), int(warmup)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        return _warm(np.full(batch.shape, self.value), self.warmup)  # (B, T)


class RandomModel:
    """Surprise at frame t drawn from an exponential seeded by a running hash of frames and states
    0..t: deterministic, causal, invariant to batch, order and keys, and chance-level (matched clips
    share their draws until they differ, then draw independently)."""

    observation = "states"

    def __init__(self, seed: int = 0) -> None:
        self.name = f"random-{seed}"
        self.seed = int(seed)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        B, T = batch.shape
        out = np.empty((B, T))
        for b in range(B):
            h = hashlib.sha256(f"voe-random:{self.seed}".encode())
            for t in range(T):
                h.update(batch.frames[b, t].tobytes() + batch.states[b, t].tobytes())
                out[b, t] = _rng(h.digest(), self.seed).exponential(1.0)
        return out  # (B, T)


class PixelSumModel:
    """A frame-only scorer: surprise is a fixed function of the current frame's pixels alone."""

    observation = "frames"

    def __init__(self, scale: float = 1e-4) -> None:
        self.name = "pixel-sum"
        self.scale = float(scale)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        f = batch.frames.astype(np.float64)  # (B, T, H, W)
        return self.scale * (f ** 2).sum(axis=(2, 3))  # (B, T)


class NoisyModel:
    """A stochastic surrogate: ``1 + sigma * noise`` per frame, the noise drawn from the clip's
    seed (``batch.seeds``), as a denoising loss draws its timesteps and noise."""

    observation = "frames"
    surprise_kind = "bound"

    def __init__(self, sigma: float = 1.0) -> None:
        self.name, self.sigma = "noisy", float(sigma)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        B, T = batch.shape
        seeds = batch.seeds or tuple(range(B))
        noise = np.stack([np.random.default_rng(s).normal(size=T) for s in seeds])  # (B, T)
        return _warm(1.0 + self.sigma * np.abs(noise))


class CheatingModel:
    """A perfect scorer for end-to-end tests: it is handed the answer key.

    Args:
        probes: the probe-set directory; its index says which clip (by opaque key) is impossible
            and where its onset is.
        jump: extra surprise from the onset of an impossible clip on.
        surprise_kind: what it declares its surprise to be (``nll``, ``bound`` or ``error``).
    """

    observation = "frames"

    def __init__(self, probes: str | Path, jump: float = 5.0, surprise_kind: str = "nll") -> None:
        from voe.io.clipkey import clip_key
        from voe.io.probeset import load_probe_set

        ps = load_probe_set(probes)
        sha = ps.manifest_sha256
        self.name, self.jump, self.surprise_kind = "cheating", float(jump), surprise_kind
        self.onset = {clip_key(sha, str(r.clip_id)): int(r.onset_frame)
                      for r in ps.index.itertuples() if r.role == "impossible"}

    def frame_nll(self, batch: Batch) -> np.ndarray:
        out = np.ones(batch.shape)  # (B, T)
        for b, key in enumerate(batch.clip_ids):
            if key in self.onset:
                out[b, max(self.onset[key], 0):] += self.jump
        return out


class IdReaderModel:
    """Cheats by reading ``batch.clip_ids``: perfect if ids name roles, chance if they are opaque."""

    observation = "frames"

    def __init__(self, jump: float = 5.0) -> None:
        self.name, self.jump = "id-reader", float(jump)

    def frame_nll(self, batch: Batch) -> np.ndarray:
        out = np.ones(batch.shape)  # (B, T)
        for b, cid in enumerate(batch.clip_ids):
            if cid.rsplit("-", 1)[-1] in _IMPOSSIBLE_VARIANTS:
                out[b] += self.jump
            else:  # an opaque key: make the most of it anyway
                out[b] += self.jump * _rng(cid, 0).random()
        return out


class PositionModel:
    """Cheats with the batch position: later clips are more surprising (in stored order a set's
    possible clips come first)."""

    observation = "frames"

    def __init__(self) -> None:
        self.name = "position"

    def frame_nll(self, batch: Batch) -> np.ndarray:
        B, T = batch.shape
        return np.repeat(np.arange(1.0, B + 1.0)[:, None], T, axis=1)  # (B, T)


class FuturePeekingModel:
    """Cheats by looking ahead: every frame's surprise is the mean per-step change of the whole
    clip, future frames included (a motion-energy statistic that no causal model can compute)."""

    observation = "frames"

    def __init__(self) -> None:
        self.name = "future-peeker"

    def frame_nll(self, batch: Batch) -> np.ndarray:
        f = batch.frames.astype(np.float64)  # (B, T, H, W)
        motion = np.abs(np.diff(f, axis=1)).mean(axis=(1, 2, 3))  # (B,)
        return _warm(np.repeat(motion[:, None], batch.shape[1], axis=1))
