"""Adapters: bring an existing model to the protocol in a few lines.

* ``TorchDistributionAdapter`` wraps a ``torch.nn.Module`` whose forward returns a
  ``torch.distributions.Distribution`` over the observation sequence.
* ``PointPredictorAdapter`` (from ``voe.models.point``) wraps a deterministic one-frame predictor
  and calibrates Gaussian noise, presence and shape probabilities on held-out possible clips.
* ``WindowPredictorAdapter`` (from ``voe.models.window``) turns an encoder and a predictor (a
  V-JEPA-style video model) into a causal per-frame representation error
  (``surprise_kind = "error"``), averaged or maximised over sliding windows.

Why: most simulators people want to test either already output a distribution (world models)
or only a point prediction (physics engines, regressors); both become true likelihoods here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.errors import ModelContractError
from voe.io.batch import Batch
from voe.models.point import PointPredictorAdapter
from voe.models.window import WindowPredictorAdapter

__all__ = ["PointPredictorAdapter", "TorchDistributionAdapter", "WindowPredictorAdapter",
           "observation_tensor"]


def observation_tensor(batch: Batch, observation: str):
    """What a wrapped module sees: frames ``(B, T, H, W)`` float 0..255, or states and presence
    ``(B, T, K, F + 1)`` float with absent slots' features set to 0 and presence last."""
    import torch

    if observation == "frames":
        return torch.from_numpy(batch.frames.astype(np.float32))
    st = np.nan_to_num(batch.states.astype(np.float32))
    return torch.from_numpy(np.concatenate([st, batch.present[..., None].astype(np.float32)], -1))


class TorchDistributionAdapter:
    """Wrap ``module(obs) -> Distribution`` so that ``dist.log_prob(obs[:, warmup:])`` is the
    log-likelihood of frames ``warmup..T-1``, each conditioned on the frames before it only.

    Args:
        module: a causal ``torch.nn.Module``; ``obs`` is ``observation_tensor(batch, observation)``.
        observation: ``"frames"`` or ``"states"``.
        warmup: leading frames not scored (NaN).
        name: model name.

    ``log_prob`` may return ``(B, T - warmup)`` or more trailing dims, which are summed.
    """

    def __init__(self, module: Any, observation: str = "states", warmup: int = 1, name: str = "torch") -> None:
        self.module, self.observation, self.warmup, self.name = module, observation, int(warmup), name

    def frame_nll(self, batch: Batch) -> np.ndarray:
        import torch

        obs = observation_tensor(batch, self.observation)
        self.module.eval()
        with torch.no_grad():
            dist = self.module(obs)
            if not isinstance(dist, torch.distributions.Distribution):
                raise ModelContractError(f"model '{self.name}': module returned {type(dist).__name__}, "
                                         f"not a torch.distributions.Distribution")
            lp = dist.log_prob(obs[:, self.warmup:])
        B, T = batch.shape
        if lp.dim() < 2 or tuple(lp.shape[:2]) != (B, T - self.warmup):
            raise ModelContractError(f"model '{self.name}': log_prob has shape {tuple(lp.shape)}, expected "
                                     f"({B}, {T - self.warmup}, ...)")
        lp = lp.reshape(B, T - self.warmup, -1).sum(-1).double().numpy()
        out = np.full((B, T), np.nan)
        out[:, self.warmup:] = -lp
        return out
