"""Where a torch model runs (``--device``) and in what precision (``--bf16``).

Why here: the protocol knows nothing about devices; a model that can move says so with a
``to(device)`` method (``voe.models.torchbase.TorchModel`` has one), and the harness calls it once.
bf16 autocast wraps each ``frame_nll`` call, so a model need not know about it either. torch is
imported only when one of the two is asked for, so scoring numpy models never loads it.
"""

from __future__ import annotations

import contextlib
from typing import Any

from voe.errors import VoeError


def place(model: Any, device: str | None) -> None:
    """Move ``model`` to ``device`` (no-op for ``None``); refuse a model that cannot move."""
    if device is None:
        return
    mover = getattr(model, "to", None)
    if not callable(mover):
        if device == "cpu":
            return
        name = getattr(model, "name", type(model).__name__)
        raise VoeError(f"model '{name}' has no to(device) method, so it cannot be run on {device}; "
                       "drop --device or add the method")
    import torch

    try:
        torch.device(device)
    except (RuntimeError, TypeError) as exc:
        raise VoeError(f"--device {device!r} is not a torch device: {exc}") from exc
    mover(device)


def precision(device: str | None, bf16: bool) -> contextlib.AbstractContextManager:
    """A bf16 autocast context for ``device`` when ``bf16``, else a no-op."""
    if not bf16:
        return contextlib.nullcontext()
    import torch

    kind = torch.device(device or "cpu").type
    return torch.autocast(device_type=kind, dtype=torch.bfloat16)
