"""Pixel model: a small convolutional predictor with recurrent (ConvGRU) memory.

Observation space: the binarised frame (``voe.models.framecopy.binarise``), scored with an
independent Bernoulli per pixel given all previous frames, so its surprise is directly comparable
with frame copy's. The output logit adds a learned multiple of the current frame (a frame-copy
skip path) to the decoder's correction. The skip weight and the output layers start at zero, so an
*untrained* model is uniform over binary frames and knows nothing, not even that frames persist
(the validity controls need untrained networks at chance); it is scaled by ``COPY_SCALE`` so that training finds frame copy within a few hundred
steps and then only has to learn motion.

Shapes: frames (B, T, H, W) -> encoder (B, C, H/4, W/4) -> ConvGRU state -> 16 logits per 4x4
block, pixel-shuffled to (B, 1, H, W), plus a 3x3 convolution of the current frame at full size.
Everything heavy runs at H/4 so that a CPU preset trains in minutes.
References: Shi et al. 2015 (ConvLSTM); Ballas et al. 2016 (ConvGRU).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import torch
from torch import nn

from voe.io.batch import Batch
from voe.models.framecopy import THRESHOLD, binarise
from voe.models.torchbase import TorchModel

COPY_SCALE = 6.0


@dataclass(frozen=True)
class PixelConfig:
    channels: int = 16
    seed: int = 0


class PixelNet(nn.Module):
    def __init__(self, c: PixelConfig) -> None:
        super().__init__()
        ch = c.channels
        self.enc = nn.Sequential(nn.Conv2d(1, ch, 4, 2, 1), nn.SiLU(), nn.Conv2d(ch, ch, 4, 2, 1), nn.SiLU())
        self.gates = nn.Conv2d(2 * ch, 2 * ch, 3, 1, 1)
        self.cand = nn.Conv2d(2 * ch, ch, 3, 1, 1)
        self.dec = nn.Sequential(nn.Conv2d(ch, ch, 3, 1, 1), nn.SiLU(), nn.Conv2d(ch, 16, 3, 1, 1),
                                 nn.PixelShuffle(4))
        self.local = nn.Conv2d(1, 1, 5, 1, 2)
        self.copy = nn.Parameter(torch.tensor(0.0))  # x COPY_SCALE: ~6 = frame copy's confidence
        self.ch = ch
        # Output layers start at zero: the untrained model gives every pixel probability 1/2, a
        # uniform likelihood that ties every matched set (the untrained-network validity control).
        # Their gradients are non-zero, so training starts at once.
        for layer in (self.dec[2], self.local):
            nn.init.zeros_(layer.weight)
            nn.init.zeros_(layer.bias)

    def randomize(self, gen: torch.Generator) -> None:
        """For random-network controls: the copy weight drawn like the weight of a one-input
        linear layer (``U(-1, 1)`` effective), so random networks range from anti-copy to a weak
        copy instead of all sharing the untrained "no copy" (the zero output layers are drawn by
        ``TorchModel.randomize_outputs``)."""
        with torch.no_grad():
            self.copy.copy_((2 * torch.rand((), generator=gen) - 1) / COPY_SCALE)

    def forward(self, bits: torch.Tensor) -> torch.Tensor:
        """Logits ``(B, T-1, H, W)`` for frames 1..T-1 from bits ``(B, T, H, W)``."""
        B, T, H, W = bits.shape
        x = bits.float() * 2 - 1
        hid = x.new_zeros(B, self.ch, H // 4, W // 4)
        out = []
        for t in range(T - 1):
            f = x[:, t : t + 1]  # (B, 1, H, W)
            e = self.enc(f)  # (B, C, H/4, W/4)
            z, r = torch.sigmoid(self.gates(torch.cat([e, hid], 1))).chunk(2, 1)
            c = torch.tanh(self.cand(torch.cat([e, r * hid], 1)))
            hid = (1 - z) * hid + z * c
            d = self.dec(hid)  # (B, 1, H, W)
            out.append((d + self.local(f))[:, 0] + COPY_SCALE * self.copy * f[:, 0])
        return torch.stack(out, 1)


class PixelModel(TorchModel):
    """Learned pixel model (see the module docstring)."""

    Config = PixelConfig
    observation = "frames"
    #: training presets: clips (windows) per step, window length in frames, learning rate, steps
    presets = {"cpu": {"batch": 8, "window": 12, "lr": 2e-3, "steps": 400},
               "cuda": {"batch": 32, "window": 40, "lr": 1e-3, "steps": 2000}}
    model_id = "pixel-v1"

    def build(self) -> nn.Module:
        return PixelNet(self.config)

    def prepare(self, batch: Batch) -> dict[str, torch.Tensor]:
        return {"bits": torch.from_numpy(binarise(batch.frames))}

    def nll(self, d: dict[str, torch.Tensor]) -> torch.Tensor:
        bits = d["bits"]
        logits = self.net(bits)  # (B, T-1, H, W)
        target = bits[:, 1:].float()
        per_pix = nn.functional.binary_cross_entropy_with_logits(logits, target, reduction="none")
        frame = per_pix.sum((2, 3))  # (B, T-1)
        return torch.cat([torch.zeros_like(frame[:, :1]), frame], 1)

    def batch_layout(self, batch: Batch) -> dict[str, Any]:
        return {"frame_size": list(batch.frames.shape[2:]), "threshold": THRESHOLD}
