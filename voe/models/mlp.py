"""Flat Gaussian MLP: all slots' features in one vector, no object structure.

Why: the baseline that shows what object structure buys. It sees exactly the inputs of the
interaction network (``voe.models.features``), concatenated over the K slots, and predicts every
slot's presence, shape and Gaussian (``voe.models.state_head``) from that one vector.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import torch
from torch import nn

from voe.io.batch import Batch
from voe.models import features as ft
from voe.models.state_head import OUT, StateHead, state_nll
from voe.models.torchbase import TorchModel


@dataclass(frozen=True)
class MLPConfig:
    n_slots: int = 4
    hidden: int = 256
    layers: int = 3
    seed: int = 0


class FlatNet(nn.Module):
    def __init__(self, c: MLPConfig) -> None:
        super().__init__()
        dims = [c.n_slots * ft.D] + [c.hidden] * c.layers
        mods: list[nn.Module] = []
        for a, b in zip(dims[:-1], dims[1:], strict=True):
            mods += [nn.Linear(a, b), nn.SiLU()]
        self.body = nn.Sequential(*mods, nn.Linear(c.hidden, c.n_slots * OUT))
        self.head = StateHead()
        nn.init.zeros_(self.body[-1].weight)  # untrained = the same prediction for every input
        nn.init.zeros_(self.body[-1].bias)
        self.k = c.n_slots

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        B, T, K, D = x.shape
        return self.body(x.reshape(B, T, K * D)).reshape(B, T, K, OUT)  # (B, T, K, OUT)


def to_tensors(batch: Batch) -> dict[str, torch.Tensor]:
    return {k: torch.from_numpy(v) for k, v in ft.slot_features(batch).items()}


class FlatMLP(TorchModel):
    """Learned state model without object structure (see the module docstring)."""

    Config = MLPConfig
    observation = "states"
    #: training presets: clips (windows) per step, window length in frames, learning rate
    presets = {"cpu": {"batch": 256, "window": 2, "lr": 2e-3}, "cuda": {"batch": 2048, "window": 2, "lr": 2e-3}}
    model_id = "mlp-v1"

    def build(self) -> nn.Module:
        return FlatNet(self.config)

    def prepare(self, batch: Batch) -> dict[str, torch.Tensor]:
        return to_tensors(batch)

    def nll(self, d: dict[str, torch.Tensor]) -> torch.Tensor:
        out = self.net(d["x"][:, :-1])  # (B, T-1, K, OUT)
        return state_nll(out, self.net.head, d)

    def batch_layout(self, batch: Batch) -> dict[str, Any]:
        return ft.layout(batch)
