"""The model protocol: one attribute pair and one method.

A model is any object with::

    name: str
    observation: "frames" | "states"
    frame_nll(batch: Batch) -> np.ndarray  # (B, T) nats, NaN for frames it does not score

``frame_nll[b, t]`` is ``-log p(observation_t | observations_<t)`` of clip ``b`` in nats: a true
(normalised) likelihood, so that surprises of different models are in the same unit. Frames the
model does not score (warm-up) are NaN; every other value must be finite. It may use frames
``0..t`` of clip ``b`` only (causality), and must not depend on the clip's key, its batch-mates or
its position in the batch (``check_model`` tests all of this).

A model that cannot give exact nats declares what it gives instead, as an optional attribute::

    surprise_kind: "nll" (default) | "bound" (an ELBO or denoising surrogate) | "error"
                   (a representation-space prediction error, unitless)

Rank-based metrics and verdicts (accuracy, CIs, p-values, AUROC) work for every kind; relative
surprise and the nats tie tolerance apply to ``nll`` only. A stochastic scorer draws its noise from
``batch.seeds``: every clip of a matched set gets the same seed (common random numbers).

Why so small: like lm-evaluation-harness's three batch methods, a tiny surface makes it trivial
to wrap any simulator or world model, and lets one checker (``check_model``) police the contract.
"""

from __future__ import annotations

from typing import Literal, Protocol, runtime_checkable

import numpy as np

from voe.io.batch import Batch

Observation = Literal["frames", "states"]
SurpriseKind = Literal["nll", "bound", "error"]

__all__ = ["Batch", "Model", "Observation", "SurpriseKind"]


@runtime_checkable
class Model(Protocol):
    """Structural type of a scoreable model (see the module docstring)."""

    name: str
    observation: Observation

    def frame_nll(self, batch: Batch) -> np.ndarray:
        """Per-frame surprise ``(B, T)`` in nats; NaN where not scored."""
        ...
