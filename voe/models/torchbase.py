"""What every learned (torch) model shares: config, seeding, scoring, weights in and out.

Why: learned models differ only in their network and in how a batch becomes tensors; the
protocol method, evaluation mode, seeding and the checkpoint's view of the weights are the same.
A subclass sets ``Config`` (a frozen dataclass), ``observation`` and ``warmup``, and implements
``build`` (the ``nn.Module``), ``prepare`` (batch -> tensors) and ``nll`` (tensors -> ``(B, T)``
surprise, NaN-free, meaningless before ``warmup``). Training code lives in ``voe.models.train``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, fields
from typing import Any, ClassVar

import numpy as np
import torch

from voe.errors import CheckpointError
from voe.io.batch import Batch

#: Largest size an integer config field may take (``seed`` excepted), and largest network a
#: config may build. Why: a config comes from a checkpoint's ``config.json``, which may be damaged
#: or hostile; ``hidden = 10**12`` or ``layers = 10**9`` must be refused in one line, not fill memory
#: or loop for hours. voe's networks have well under a million parameters.
MAX_SIZE, MAX_PARAMS = 1 << 16, 100_000_000


def check_config(config: Any) -> None:
    """Refuse a config whose fields are not what their types say, or that builds an absurd network.

    Raises:
        TypeError: naming the field (``voe.models.loading`` turns it into a one-line error).
    """
    for f in fields(config):
        v, kind = getattr(config, f.name), f.type if isinstance(f.type, str) else f.type.__name__
        if kind == "int":
            top = 1 << 63 if f.name == "seed" else MAX_SIZE
            if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= top:
                raise TypeError(f"config field {f.name} must be an integer in [0, {top}], got {v!r}")
        elif kind == "float" and (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)):
            raise TypeError(f"config field {f.name} must be a finite number, got {v!r}")


class TorchModel:
    """Base class of the learned models (see the module docstring)."""

    Config: ClassVar[type]
    observation: ClassVar[str]
    warmup: ClassVar[int] = 1
    model_id: ClassVar[str]
    device: str = "cpu"

    def __init__(self, **kwargs: Any) -> None:
        known = {f.name for f in fields(self.Config)}
        unknown = sorted(set(kwargs) - known)
        if unknown:
            raise TypeError(f"unexpected argument(s) {unknown}; {type(self).__name__} takes {sorted(known)}")
        self.config = self.Config(**kwargs)
        check_config(self.config)
        self.name = self.model_id.split("-v")[0]
        with torch.device("meta"):  # sized without allocating: a damaged config must not fill memory
            n = sum(p.numel() for p in self.build().parameters())
        if n > MAX_PARAMS:
            raise TypeError(f"config {asdict(self.config)} builds {n:,} parameters (at most {MAX_PARAMS:,})")
        torch.manual_seed(self.config.seed)
        self.net: torch.nn.Module = self.build()
        self.layout: dict[str, Any] | None = None  # set by training / checkpoint

    # -- hooks ---------------------------------------------------------------------------
    def build(self) -> torch.nn.Module:
        raise NotImplementedError

    def prepare(self, batch: Batch) -> dict[str, torch.Tensor]:
        raise NotImplementedError

    def nll(self, data: dict[str, torch.Tensor]) -> torch.Tensor:
        raise NotImplementedError

    def batch_layout(self, batch: Batch) -> dict[str, Any]:
        raise NotImplementedError

    # -- protocol ----------------------------------------------------------------------------
    def frame_nll(self, batch: Batch) -> np.ndarray:
        self.check_layout(batch)
        self.net.eval()
        with torch.no_grad():
            data = {k: v.to(self.device) if isinstance(v, torch.Tensor) else v
                    for k, v in self.prepare(batch).items()}
            out = self.nll(data).double().cpu().numpy().copy()  # (B, T)
        out[:, : self.warmup] = np.nan
        return out

    def to(self, device: str) -> TorchModel:
        """Run on ``device`` (``voe score --device``): the weights move, batches follow."""
        self.device = str(device)
        self.net.to(self.device)
        return self

    def randomize_outputs(self, seed: int) -> None:
        """Give every parameter that is zero or fixed at initialisation a random value.

        Why: a learned model starts with zero output layers, closed gates and a fixed "typical"
        state so that, untrained, it is uniform (a constant: it ties every matched set by
        construction). A *random network* validity control must be a random function of its
        inputs with *nothing* left at a shared initial value: a closed gate kept closed in every
        random network (as interaction-v2's once were) makes the control sample a smaller family
        than the architecture, one that cannot fail where the gate matters. This draws every
        all-zero linear or convolutional layer from the default ``U(-1/sqrt(fan_in), ...)`` and
        lets modules with a ``randomize(generator)`` method (state heads, the pixel model's copy
        weight) draw their own, each over its natural range (the method's docstring says why).
        ``tests/controls/test_random_nets.py`` fails for any parameter left shared by two seeds.
        """
        gen = torch.Generator().manual_seed(int(seed))
        with torch.no_grad():
            for m in self.net.modules():
                if isinstance(m, torch.nn.Linear | torch.nn.Conv2d) and not m.weight.any():
                    bound = 1.0 / float(np.sqrt(m.weight[0].numel()))
                    m.weight.uniform_(-bound, bound, generator=gen)
                    if m.bias is not None:
                        m.bias.uniform_(-bound, bound, generator=gen)
                if hasattr(m, "randomize"):
                    m.randomize(gen)

    # -- checkpoints -------------------------------------------------------------------------
    def check_layout(self, batch: Batch) -> None:
        """Refuse a batch whose features differ from the ones the weights were trained on."""
        if self.layout is None:
            return
        have = self.batch_layout(batch)
        diff = [k for k in self.layout if have.get(k) != self.layout[k]]
        if diff:
            k = diff[0]
            raise CheckpointError(f"{self.name}: checkpoint was trained with {k}={self.layout[k]}, "
                                  f"this data has {k}={have.get(k)}; retrain on matching data")

    def config_dict(self) -> dict[str, Any]:
        return asdict(self.config)

    def weights(self) -> dict[str, torch.Tensor]:
        return {k: v.detach().cpu().contiguous() for k, v in self.net.state_dict().items()}

    def load_weights(self, tensors: dict[str, torch.Tensor], source: str) -> None:
        want = self.net.state_dict()
        missing, extra = sorted(set(want) - set(tensors)), sorted(set(tensors) - set(want))
        bad = [k for k in want if k in tensors and tuple(tensors[k].shape) != tuple(want[k].shape)]
        if missing or extra or bad:
            what = (f"missing {missing[:3]}" if missing else f"unexpected {extra[:3]}" if extra
                    else f"shape of {bad[0]} is {tuple(tensors[bad[0]].shape)}, expected {tuple(want[bad[0]].shape)}")
            raise CheckpointError(f"{source} does not fit {self.model_id} with config {self.config_dict()}: {what}")
        self.net.load_state_dict(tensors)
