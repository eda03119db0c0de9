"""Flat Gaussian MLP over a short window of observed states: no object structure, no memory.

Why: the baseline that shows what object structure and memory buy. It sees the last ``k``
observed frames of every slot (``voe.models.statelik.CONT`` features, shape and presence; a
hidden or absent slot is zeros with presence 0), concatenated over slots and frames, and
predicts every slot's presence, shape and Gaussian at the next frame from that one vector.
Nothing is carried by hand: no constant-velocity guess, no memory of hidden objects (the
previous version read both from a hand-made feature module, and random networks of it were off
chance on six concept cells). An object hidden for more than ``k`` frames is forgotten.

The mean is ``c + S * (body(x) + skip(x))`` per feature, where ``S`` undoes the input scaling and
``skip`` is a linear map of the window (a learned autoregression); ``body``'s last layer and
``skip`` start at zero, so the untrained model is a constant. The first ``k`` frames are warm-up.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import torch
from torch import nn

from voe.io.batch import Batch
from voe.models import statelik as sl
from voe.models.state_head import TYPICAL, StateHead, bounded_logvar, frame_cost
from voe.models.torchbase import TorchModel

F_IN = 11  # per slot and frame: 9 CONT features (centred, scaled), circle, present
OUT = 20  # per slot: presence logit, 9 means, 9 log-variances, shape logit
SCALE = (10.0, 10.0, 3.0, 5.0, 5.0, 5.0, 1.0, 1.0, 1.0)  # input = (state - TYPICAL) / SCALE
LAYOUT_VERSION = 2


@dataclass(frozen=True)
class MLPConfig:
    """Slots, the window of observed frames ``k`` the model sees, width and depth, seed."""

    n_slots: int = 4
    k: int = 3
    hidden: int = 256
    layers: int = 3
    seed: int = 0


class FlatNet(nn.Module):
    def __init__(self, c: MLPConfig) -> None:
        super().__init__()
        n_in = c.k * c.n_slots * F_IN
        dims = [n_in] + [c.hidden] * c.layers
        mods: list[nn.Module] = []
        for a, b in zip(dims[:-1], dims[1:], strict=True):
            mods += [nn.Linear(a, b), nn.SiLU()]
        self.body = nn.Sequential(*mods, nn.Linear(c.hidden, c.n_slots * OUT))
        self.skip = nn.Linear(n_in, c.n_slots * OUT)
        self.head = StateHead()
        for layer in (self.body[-1], self.skip):  # untrained = the same prediction for every input
            nn.init.zeros_(layer.weight)
            nn.init.zeros_(layer.bias)
        self.k, self.n = c.k, c.n_slots

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        # x: (B, T, K, F_IN) -> (B, T, K, OUT): the output at t predicts frame t+1 from frames t-k+1..t
        B, T, K, _ = x.shape
        pad = torch.cat([x.new_zeros(B, self.k - 1, K, F_IN), x], 1)  # (B, T+k-1, K, F_IN)
        win = pad.unfold(1, self.k, 1)  # (B, T, K, F_IN, k)
        flat = win.permute(0, 1, 4, 2, 3).reshape(B, T, self.k * K * F_IN)
        return (self.body(flat) + self.skip(flat)).reshape(B, T, K, OUT)


def to_tensors(batch: Batch) -> dict[str, torch.Tensor]:
    """Observed states ``obs`` ``(B, T, K, 9)``, ``circle`` and ``present`` ``(B, T, K)`` and the
    scaled input ``x`` ``(B, T, K, F_IN)`` (zeros where a slot is not seen)."""
    idx = sl.cont_index(batch.feature_names)
    obs = np.nan_to_num(batch.states[..., idx].astype(np.float32))  # (B, T, K, 9)
    circle = (np.nan_to_num(batch.states[..., batch.feature_names.index("is_circle")]) > 0.5).astype(np.float32)
    pres = batch.present.copy()
    x = np.concatenate([(obs - np.float32(TYPICAL)) / np.float32(SCALE), circle[..., None],
                        pres[..., None].astype(np.float32)], -1) * pres[..., None]
    return {"obs": torch.from_numpy(obs), "circle": torch.from_numpy(circle), "present": torch.from_numpy(pres),
            "x": torch.from_numpy(x.astype(np.float32))}


def window_nll(net: FlatNet, d: dict[str, torch.Tensor]) -> torch.Tensor:
    """Surprise ``(B, T)`` of frame t+1 given frames t-k+1..t (frame 0 set to 0)."""
    out = net(d["x"][:, :-1])  # (B, T-1, K, OUT)
    obs, pres, circ = d["obs"][:, 1:], d["present"][:, 1:], d["circle"][:, 1:]
    if not net.head.training:  # score in float64: an untrained model's equal costs stay equal
        out, obs, circ = out.double(), obs.double(), circ.double()
    mean = out.new_tensor(TYPICAL) + out.new_tensor(SCALE) * out[..., 1:10]
    frame = frame_cost(net.head, mean, bounded_logvar(out[..., 10:19]), out[..., 0] + net.head.presence_bias(),
                       out[..., 19], obs, pres, circ)  # (B, T-1)
    return torch.cat([torch.zeros_like(frame[:, :1]), frame], 1)


class FlatMLP(TorchModel):
    """Learned state model without object structure or memory (see the module docstring)."""

    Config = MLPConfig
    observation = "states"
    #: training presets: windows per step, window length in frames (the loss counts the frames
    #: after the first k), learning rate, steps
    presets = {"cpu": {"batch": 256, "window": 8, "lr": 2e-3, "steps": 1500},
               "cuda": {"batch": 2048, "window": 8, "lr": 2e-3, "steps": 4000}}
    model_id = "mlp-v2"

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.warmup = self.config.k  # frames before the first full window are not scored

    def build(self) -> nn.Module:
        return FlatNet(self.config)

    def prepare(self, batch: Batch) -> dict[str, torch.Tensor]:
        return to_tensors(batch)

    def nll(self, d: dict[str, torch.Tensor]) -> torch.Tensor:
        return window_nll(self.net, d)

    def batch_layout(self, batch: Batch) -> dict[str, Any]:
        return {"feature_names": list(batch.feature_names), "n_slots": int(batch.states.shape[2]),
                "input_dim": F_IN, "window": self.config.k, "layout_version": LAYOUT_VERSION}
