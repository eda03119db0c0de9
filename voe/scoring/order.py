"""The order in which clips are shown to a model, and what each batch may reveal.

Why: a harness that scores a matched set's clips side by side, in stored order, hands a model
the answer (the possible clips come first; position in the batch is the role). Here clips are
shown in a seeded shuffled order, each batch holds at most one clip of any matched set, and the
batch carries opaque clip keys (``voe.io.clipkey``) instead of role-bearing ids.

The schedule is a pure function of the probe-set index, the batch size and the seed:

* matched sets are shuffled (within groups of equal size, so batches stay full) and cut into
  *groups* of ``batch_size`` sets;
* within a group, the clips of every set are shuffled, and batch ``j`` of the group holds the
  ``j``-th clip of each set. So a set's clips always land in different batches.

Groups are also the unit of data-parallel sharding (``voe.scoring.distributed``): every clip is
scored in the same batch whatever the number of ranks, which is what makes a sharded run
byte-identical to a single-process one.
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from voe.io.batch import Batch
from voe.io.clipkey import clip_key, set_key

#: How per-clip seeds are derived; recorded in ``run.json``.
CRN_RULE = "seed of a clip = first 8 bytes (little endian) of sha256('voe-crn:{seed}:{set_key}') >> 1"


@dataclass(frozen=True)
class Schedule:
    """Batches of clip ids, in the order they are scored.

    Attributes:
        batches: clip ids per batch; every clip of the probe set exactly once.
        group: for each batch, the index of its group of matched sets (the sharding unit).
        seed: the seed that made the order.
    """

    batches: tuple[tuple[str, ...], ...]
    group: tuple[int, ...]
    seed: int

    @property
    def n_groups(self) -> int:
        return (max(self.group) + 1) if self.group else 0

    def for_rank(self, rank: int, world: int) -> list[int]:
        """Indices of the batches rank ``rank`` of ``world`` scores (groups dealt round-robin)."""
        return [i for i, g in enumerate(self.group) if g % world == rank]


def crn_seed(seed: int, skey: str) -> int:
    """The common-random-number seed of every clip of the matched set with key ``skey``."""
    digest = hashlib.sha256(f"voe-crn:{seed}:{skey}".encode()).digest()
    return int.from_bytes(digest[:8], "little") >> 1  # fits int64


def _set_ids(index: pd.DataFrame) -> pd.Series:
    """Matched-set id of every clip; a clip without one (training worlds) is its own set."""
    if "set_id" not in index.columns:
        return index["clip_id"].astype(str)
    sid = index["set_id"]
    return sid.where(sid.notna(), index["clip_id"]).astype(str)


def plan(index: pd.DataFrame, batch_size: int, seed: int = 0) -> Schedule:
    """Shuffle ``index`` (one row per clip, ``clip_id`` and ``set_id``) into a :class:`Schedule`."""
    if batch_size < 1:
        raise ValueError("batch_size must be >= 1")
    rng = np.random.default_rng(seed)
    sets: dict[str, list[str]] = {}
    for cid, sid in zip(index["clip_id"].astype(str), _set_ids(index), strict=True):
        sets.setdefault(sid, []).append(cid)
    by_size: dict[int, list[str]] = {}
    for sid in sorted(sets):
        by_size.setdefault(len(sets[sid]), []).append(sid)
    groups: list[list[str]] = []
    for size in sorted(by_size):
        ids = [by_size[size][i] for i in rng.permutation(len(by_size[size]))]
        groups += [ids[i:i + batch_size] for i in range(0, len(ids), batch_size)]
    batches, group = [], []
    for g, i in enumerate(rng.permutation(len(groups))):
        members = [[sorted(sets[s])[j] for j in rng.permutation(len(sets[s]))] for s in groups[i]]
        for j in range(max(len(m) for m in members)):
            batches.append(tuple(m[j] for m in members if j < len(m)))
            group.append(g)
    return Schedule(tuple(batches), tuple(group), int(seed))


class Blinder:
    """Makes the batches a model sees for one probe set: opaque keys and CRN seeds per clip.

    Args:
        ps: a ``voe.io.probeset.ProbeSet`` (only its public ``batch``, ``index`` and
            ``manifest_sha256`` are used).
        seed: the run's seed, from which every matched set's common-random-number seed is drawn.
    """

    def __init__(self, ps, seed: int = 0) -> None:
        self.ps, self.seed = ps, int(seed)
        sha = ps.manifest_sha256
        ids = ps.index["clip_id"].astype(str).tolist()
        sids = _set_ids(ps.index).tolist()
        self.key = {c: clip_key(sha, c) for c in ids}
        self.clip_id = {k: c for c, k in self.key.items()}
        set_seed = {s: crn_seed(self.seed, set_key(sha, s)) for s in set(sids)}
        self.set_of = dict(zip(ids, sids, strict=True))
        self.crn = {c: set_seed[s] for c, s in self.set_of.items()}

    def batch(self, clip_ids: Sequence[str]) -> Batch:
        """The model-facing batch for ``clip_ids`` (real ids in, opaque keys out)."""
        batch = self.ps.batch(list(clip_ids))
        return dataclasses.replace(batch, clip_ids=tuple(self.key[c] for c in clip_ids),
                                   seeds=tuple(self.crn[c] for c in clip_ids))

    def sample(self, sched: Schedule, n: int) -> list[str]:
        """The first ``n`` clips of ``sched``'s order that come from distinct matched sets."""
        seen, ids = set(), []
        for cid in (c for b in sched.batches for c in b):
            if self.set_of[cid] not in seen and len(ids) < n:
                seen.add(self.set_of[cid])
                ids.append(cid)
        return ids

    def describe(self, key: str) -> str:
        """``key (clip id)`` for error messages, which the user (not the model) reads."""
        return f"{key} (clip {self.clip_id.get(key, '?')})"
