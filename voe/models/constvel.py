"""Constant velocity with a calibrated Gaussian: the reference every state model must beat.

Each object keeps its observed velocity for one frame; occluded objects are carried forward at
constant velocity and scored against that carried state when they reappear. Noise, presence and
shape probabilities are fitted by maximum likelihood (``voe train constvel --data DIR``) and
stored in the checkpoint, or passed as ``--model-arg noise=...`` from Python.
"""

from __future__ import annotations

from typing import Any

from voe.models.point import PointPredictorAdapter, _constant_velocity


class ConstantVelocity(PointPredictorAdapter):
    """Reference state model (see the module docstring)."""

    def __init__(self, noise: dict[str, Any] | None = None) -> None:
        super().__init__(_constant_velocity, noise, name="constvel")
