"""Object-centric interaction network with per-slot memory, presence and a Gaussian head.

Why: physical expectations are about objects, so each slot is encoded on its own (its memory:
last seen state carried forward while hidden, its nearest static segments, whether it should be
visible next frame; see ``voe.models.features``), objects exchange messages along all pairs
(relative position and velocity, the gap between them and the frames until they touch), and each slot predicts its own next
state (``voe.models.state_head``). Teacher-forced on the true past, one step ahead.

References: Battaglia et al. 2016, "Interaction Networks for Learning about Objects, Relations
and Physics"; Piloto et al. 2022 (PLATO), object-centric VoE surprise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import torch
from torch import nn

from voe.io.batch import Batch
from voe.models import features as ft
from voe.models.mlp import to_tensors
from voe.models.state_head import OUT, StateHead, state_nll
from voe.models.torchbase import TorchModel


@dataclass(frozen=True)
class InteractionConfig:
    hidden: int = 96
    seed: int = 0


def mlp(a: int, h: int, b: int) -> nn.Sequential:
    return nn.Sequential(nn.Linear(a, h), nn.SiLU(), nn.Linear(h, h), nn.SiLU(), nn.Linear(h, b))


class InteractionModule(nn.Module):
    def __init__(self, c: InteractionConfig) -> None:
        super().__init__()
        h = c.hidden
        self.node = mlp(ft.D, h, h)
        self.edge = mlp(2 * h + ft.REL, h, h)
        self.out = mlp(2 * h + ft.D, h, OUT)
        self.head = StateHead()
        nn.init.zeros_(self.out[-1].weight)  # untrained = the same prediction for every input
        nn.init.zeros_(self.out[-1].bias)

    def forward(self, x: torch.Tensor, rel: torch.Tensor) -> torch.Tensor:
        # x: (B, T, K, D); rel: (B, T, K, K, REL) with [k, j] = other j seen from k
        B, T, K, D = x.shape
        h = self.node(x)  # (B, T, K, H)
        pair = torch.cat([h[:, :, :, None].expand(B, T, K, K, -1), h[:, :, None].expand(B, T, K, K, -1), rel], -1)
        mask = rel[..., -1:]  # other known (zero on the diagonal)
        msg = (self.edge(pair) * mask).sum(3)  # (B, T, K, H)
        return self.out(torch.cat([h, msg, x], -1))  # (B, T, K, OUT)


class InteractionNet(TorchModel):
    """Learned object-centric state model (see the module docstring)."""

    Config = InteractionConfig
    observation = "states"
    #: training presets: clips (windows) per step, window length in frames, learning rate
    presets = {"cpu": {"batch": 256, "window": 2, "lr": 2e-3}, "cuda": {"batch": 2048, "window": 2, "lr": 2e-3}}
    model_id = "interaction-v1"

    def build(self) -> nn.Module:
        return InteractionModule(self.config)

    def prepare(self, batch: Batch) -> dict[str, torch.Tensor]:
        return to_tensors(batch)

    def nll(self, d: dict[str, torch.Tensor]) -> torch.Tensor:
        return state_nll(self.net(d["x"][:, :-1], d["rel"][:, :-1]), self.net.head, d)

    def batch_layout(self, batch: Batch) -> dict[str, Any]:
        return ft.layout(batch)
