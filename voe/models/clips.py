"""Training and validation clips read from a sharded set a bounded number at a time.

Why: ``voe train`` used to load the whole training set as one ``Batch`` (and the model's tensors
of it), so memory grew with the world: a 100k-clip world would not fit. Here the training clips
are cut into *groups* of whole shards holding at most ``capacity`` clips; training keeps one group
in memory and moves to the next after a fixed number of steps (``GroupSampler``), and validation
streams its clips in chunks. A set that fits in one group is loaded once, exactly as before.
Torch-free.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import numpy as np

from voe.io.batch import Batch
from voe.io.probeset import ProbeSet


class Clips:
    """Some clips of a probe or training set, by id, read from its shards on demand."""

    def __init__(self, ps: ProbeSet, ids: Sequence[str]) -> None:
        self.ps, self.ids = ps, list(ids)

    def __len__(self) -> int:
        return len(self.ids)

    def load(self, ids: Sequence[str] | None = None) -> Batch:
        """One in-memory ``Batch`` of ``ids`` (default: all of these clips)."""
        return self.ps.batch(self.ids if ids is None else list(ids))

    def batches(self, size: int = 64) -> Iterator[Batch]:
        """Consecutive batches of at most ``size`` clips."""
        return self.ps.batches(self.ids, size)

    def groups(self, capacity: int) -> list[list[str]]:
        """The ids in groups of at most ``capacity`` clips made of whole shards (in shard order;
        a shard with more clips than ``capacity`` is cut), so loading a group reads few files."""
        shard = self.ps.shard_of(self.ps.rows(self.ids))  # (n,)
        groups: list[list[str]] = []
        cur: list[str] = []
        for s in np.unique(shard):
            members = [self.ids[i] for i in np.flatnonzero(shard == s)]
            for start in range(0, len(members), capacity):
                chunk = members[start:start + capacity]
                if cur and len(cur) + len(chunk) > capacity:
                    groups.append(cur)
                    cur = []
                cur += chunk
        if cur:
            groups.append(cur)
        return groups

    def sample(self, n: int, seed: int) -> Clips:
        """At most ``n`` of these clips, a seeded choice kept in set order."""
        if n >= len(self):
            return self
        keep = np.sort(np.random.default_rng(seed).choice(len(self), n, replace=False))
        return Clips(self.ps, [self.ids[i] for i in keep])


class MemoryClips:
    """A ``Batch`` already in memory, behind the same interface (tests and benches)."""

    def __init__(self, batch: Batch) -> None:
        self.batch = batch
        self.ids = list(batch.clip_ids) or [str(i) for i in range(len(batch))]

    def __len__(self) -> int:
        return len(self.batch)

    def load(self, ids: Sequence[str] | None = None) -> Batch:
        if ids is None or list(ids) == self.ids:
            return self.batch
        pos = {c: i for i, c in enumerate(self.ids)}
        return self.batch.take([pos[c] for c in ids])

    def batches(self, size: int = 64) -> Iterator[Batch]:
        for start in range(0, len(self.batch), size):
            yield self.batch.take(slice(start, start + size))

    def groups(self, capacity: int) -> list[list[str]]:
        return [self.ids]  # already in memory: one group

    def sample(self, n: int, seed: int) -> MemoryClips:
        return self


def as_clips(x: Batch | Clips | MemoryClips) -> Clips | MemoryClips:
    return MemoryClips(x) if isinstance(x, Batch) else x


class GroupSampler:
    """Which group of training clips is in memory: all groups in a seeded random order, epoch
    after epoch, each kept for ``steps_per_group`` optimiser steps."""

    def __init__(self, groups: list[list[str]], seed: int) -> None:
        self.groups = groups
        self.rng = np.random.default_rng([seed, 0x5A4D])  # apart from the batch sampler's stream
        self._order: list[int] = []

    def next(self) -> list[str]:
        if not self._order:
            self._order = list(self.rng.permutation(len(self.groups)))
        return self.groups[self._order.pop(0)]
