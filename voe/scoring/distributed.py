"""Data-parallel scoring: one process per device, launched by ``torchrun``, sharded by matched set.

Why: video world models are scored one process per GPU (IntPhys 2 recommends 64 for Cosmos).
Each rank scores the groups of matched sets that ``Schedule.for_rank`` deals it (whole sets, no
padded duplicates) and writes its batches to the shared cache; rank 0 then merges them by clip
key into the usual run directory. Because a clip is scored in the same batch whatever the number
of ranks, the files are byte-identical to a single-process run.

torch is imported only here, and only when ``WORLD_SIZE`` says there is more than one rank. The
process group uses gloo (CPU collectives; only a barrier and one sum are exchanged, never data).
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from typing import Any

from voe.errors import VoeError


@dataclass(frozen=True)
class Ranks:
    """This process's place in a launch (``rank`` of ``world``); the single-process default."""

    rank: int = 0
    world: int = 1
    launcher: str = "python"

    def total(self, n: int) -> int:
        """Sum ``n`` over ranks (a no-op for one process)."""
        return n

    def describe(self) -> dict[str, Any]:
        return {"name": self.launcher, "world_size": self.world}

    def close(self) -> None:
        """Leave the process group (nothing to do for one process)."""


SINGLE = Ranks()


class TorchRanks(Ranks):
    """Ranks joined in a ``torch.distributed`` gloo process group."""

    def total(self, n: int) -> int:
        import torch
        import torch.distributed as dist

        t = torch.tensor([n], dtype=torch.int64)
        dist.all_reduce(t)  # also a barrier: rank 0 merges only after every rank has written
        return int(t.item())

    def close(self) -> None:
        import torch.distributed as dist

        if dist.is_initialized():
            dist.destroy_process_group()


def from_env() -> Ranks:
    """The launch described by ``torchrun``'s environment (``RANK``, ``WORLD_SIZE``, ...)."""
    world = int(os.environ.get("WORLD_SIZE", "1") or 1)
    if world <= 1:
        return SINGLE
    rank = int(os.environ.get("RANK", "0"))
    try:
        import torch.distributed as dist
    except ImportError as exc:
        raise VoeError("WORLD_SIZE > 1 but torch is not installed; install torch to score with torchrun") from exc
    if not dist.is_initialized():
        dist.init_process_group(backend="gloo", init_method="env://")
    return TorchRanks(rank=rank, world=world, launcher="torchrun")


def rank_device(device: str | None) -> str | None:
    """``cuda`` becomes ``cuda:LOCAL_RANK`` under torchrun, so each rank gets its own GPU."""
    if device == "cuda" and int(os.environ.get("WORLD_SIZE", "1") or 1) > 1:
        return f"cuda:{int(os.environ.get('LOCAL_RANK', '0'))}"
    return device


def torchrun_argv(nproc: int, voe_args: list[str]) -> list[str]:
    """The command that re-runs ``voe voe_args`` under torchrun with ``nproc`` ranks on this node."""
    return [sys.executable, "-m", "torch.distributed.run", "--standalone", f"--nproc_per_node={nproc}",
            "-m", "voe", *voe_args]
