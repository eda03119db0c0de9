"""Representation-space prediction error over sliding windows (V-JEPA style), as a causal surprise.

Why: video world models such as V-JEPA 2 give no likelihood. Their surprise (Garrido et al. 2025,
"Intuitive physics understanding emerges from self-supervised pretraining on natural videos") is
the L1 distance between the representation a predictor expects for the coming frames and the
one the encoder computes when they arrive, over windows that slide along the video. This adapter
turns any ``encode`` and ``predict`` pair into voe's per-frame protocol with
``surprise_kind = "error"`` (unitless; rank-based metrics and verdicts apply, nats do not).

Definition (every quantity uses frames up to ``t`` only, so the surprise is causal):

* ``z_t = encode(frames[t-k+1 .. t])``: the representation of the ``k``-frame clip ending at ``t``;
* a window whose context ends at frame ``c - 1`` (``c = k, k + s, k + 2s, ...``, stride ``s``)
  predicts ``zhat_{c+i} = predict(z_{c-1}, h)[i]`` for the next ``h`` frames (``h >= s``, so every
  frame from ``k`` on is predicted by at least one window);
* its error at frame ``t = c + i`` is ``mean |zhat_t - z_t|`` over the representation's entries;
* the surprise of frame ``t`` is the **average** or the **maximum** of that error over the windows
  that predict ``t`` (``reduce``). Frames ``0 .. k-1`` are warm-up (NaN).

Both reductions are declared up front: ``WindowPredictorAdapter.variants(...)`` returns the pair
(names ``<name>-avg`` and ``<name>-max``), and both are scored and reported; picking one after
seeing results is the reporting of the best of several aggregators that STYLE.md warns about.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from voe.errors import ModelContractError
from voe.io.batch import Batch

REDUCTIONS = ("avg", "max")


def _numpy(x: Any) -> np.ndarray:
    """Arrays from numpy or torch (detached, on the CPU), as float64."""
    if hasattr(x, "detach"):
        x = x.detach().float().cpu().numpy()
    return np.asarray(x, dtype=np.float64)


class WindowPredictorAdapter:
    """Wrap ``encode`` and ``predict`` into a per-frame ``error`` surprise.

    Args:
        encode: ``(N, k, H, W, C)`` float32 frames in ``[0, 1]`` -> ``(N, ...)`` one representation
            per clip (numpy or torch). Grayscale probe sets give ``C = 1``.
        predict: ``(z (N, ...), h)`` -> ``(N, h, ...)``: the representations of the next ``h``
            frames' clips, predicted from the context's.
        context: ``k``, frames per encoded clip (the context window).
        stride: ``s``, frames between consecutive windows.
        horizon: ``h``, frames each window predicts (default ``stride``); ``h > s`` lets
            windows overlap, and then ``avg`` and ``max`` differ.
        reduce: ``"avg"`` or ``"max"`` over the windows that predict a frame.
        name: model name (``-avg``/``-max`` is appended).
        chunk: clips per ``encode`` call (memory).

    Both callables must treat the clips of a call independently (eval mode, no batch
    statistics): ``check_model`` scores a batch whole and in halves and expects the same numbers.
    """

    observation = "frames"
    surprise_kind = "error"

    def __init__(self, encode: Callable[..., Any], predict: Callable[..., Any], context: int,
                 stride: int = 1, horizon: int | None = None, reduce: str = "avg",
                 name: str = "window", chunk: int = 256) -> None:
        horizon = stride if horizon is None else horizon
        if reduce not in REDUCTIONS:
            raise ValueError(f"reduce must be one of {REDUCTIONS}, not {reduce!r}")
        if context < 1 or stride < 1 or horizon < stride:
            raise ValueError(f"need context >= 1, stride >= 1 and horizon >= stride "
                             f"(got {context}, {stride}, {horizon}): every frame must be predicted")
        self.encode, self.predict = encode, predict
        self.context, self.stride, self.horizon, self.reduce = int(context), int(stride), int(horizon), reduce
        self.name, self.chunk = f"{name}-{reduce}", int(chunk)

    @classmethod
    def variants(cls, encode: Callable[..., Any], predict: Callable[..., Any], context: int,
                 stride: int = 1, horizon: int | None = None, name: str = "window",
                 **kw: Any) -> tuple[WindowPredictorAdapter, WindowPredictorAdapter]:
        """The two declared variants, ``(avg, max)``: score and report both."""
        return tuple(cls(encode, predict, context, stride, horizon, r, name, **kw) for r in REDUCTIONS)

    # -- the protocol ------------------------------------------------------------------------
    def frame_nll(self, batch: Batch) -> np.ndarray:
        """Per-frame representation error ``(B, T)``; NaN for the first ``context`` frames."""
        B, T = batch.shape
        k, s, h = self.context, self.stride, self.horizon
        if T <= k:
            raise ModelContractError(f"model '{self.name}': clips of {T} frames leave nothing to "
                                     f"predict after a context of {k}")
        x = batch.frames.astype(np.float32) / 255.0  # (B, T, H, W[, C])
        x = x[..., None] if x.ndim == 4 else x  # (B, T, H, W, C)
        n = T - k + 1  # clips ending at frames k-1 .. T-1
        clips = np.stack([x[:, t - k + 1: t + 1] for t in range(k - 1, T)], axis=1)  # (B, n, k, H, W, C)
        flat = clips.reshape(B * n, *clips.shape[2:])
        z = np.concatenate([_numpy(self.encode(flat[i: i + self.chunk]))
                            for i in range(0, len(flat), self.chunk)])
        rep = z.shape[1:]  # the encoder's representation shape, e.g. (tokens, width)
        z = z.reshape(B, n, -1)  # (B, n, D): z[:, j] is the clip ending at frame j + k - 1
        starts = np.arange(k, T, s)  # first predicted frame of each window
        ctx = z[:, starts - k].reshape(B * len(starts), *rep)  # context clip ends at frame c - 1
        pred = _numpy(self.predict(ctx, h)).reshape(B, len(starts), h, -1)  # (B, W, h, D)
        total = np.zeros((B, T))
        count = np.zeros(T)
        worst = np.full((B, T), -np.inf)
        for w, c in enumerate(starts):
            for i in range(min(h, T - c)):
                err = np.abs(pred[:, w, i] - z[:, c + i - k + 1]).mean(axis=-1)  # (B,)
                total[:, c + i] += err
                count[c + i] += 1
                worst[:, c + i] = np.maximum(worst[:, c + i], err)
        out = np.full((B, T), np.nan)
        out[:, k:] = (total[:, k:] / count[k:]) if self.reduce == "avg" else worst[:, k:]
        return out

