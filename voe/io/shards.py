"""Sharded clip arrays: written one shard at a time, read a few rows at a time.

Why: a set used to be one stacked ``.npy`` per array, built in memory before writing, so
generating 4,000 clips peaked at 2.1 GB and 100k clips would need about 50 GB. Here clips go
into a preallocated shard buffer as they are made; a full shard is written, hashed and dropped.
Readers open a shard's file memory-mapped, copy the rows asked for, and keep only the last few
shards mapped, so neither side's memory grows with the number of clips.

Layout (inside a set's directory)::

    shards/00000/frames.npy    (n, T, H, W) uint8    n <= shard_clips
    shards/00000/states.npy    (n, T, K, F) float32
    shards/00000/present.npy   (n, T, K) bool
    shards/00000/exists.npy    (n, T, K) bool
    shards/00001/...

Shard sizes depend only on the clip shape, so the same seed gives the same shards whatever the
number of worker processes.
"""

from __future__ import annotations

import re
from collections import OrderedDict
from pathlib import Path
from typing import Any

import numpy as np

from voe.errors import ProbeSetError
from voe.io.provenance import sha256_file

SHARD_BYTES = 64 << 20  # a shard's four files together stay under about 64 MiB
MAX_SHARD_CLIPS = 256
SHARD_DIR = re.compile(r"^shards/\d{5}$")  # the only shard paths a manifest may name
OPEN_SHARDS = 2  # shards kept memory-mapped per array (sequential readers hit the cache)


def shard_clips(bytes_per_clip: int) -> int:
    """Clips per shard for clips of ``bytes_per_clip`` bytes (all arrays together)."""
    return int(max(1, min(MAX_SHARD_CLIPS, SHARD_BYTES // max(bytes_per_clip, 1))))


class ShardWriter:
    """Collects clips (dicts of equally named arrays) into shards under ``root/shards``."""

    def __init__(self, root: Path, dtypes: dict[str, Any]) -> None:
        self.root, self.dtypes = Path(root), {k: np.dtype(v) for k, v in dtypes.items()}
        self.files: dict[str, str] = {}  # relative path -> sha256
        self.shards: list[dict[str, Any]] = []  # {"path": "shards/00000", "n_clips": n}
        self._buf: dict[str, np.ndarray] | None = None
        self._n = 0
        self.capacity = 0

    def add(self, arrays: dict[str, np.ndarray]) -> None:
        """Append one clip; writes the shard when it is full."""
        if self._buf is None:
            if not self.capacity:
                self.capacity = shard_clips(sum(np.asarray(a).size * self.dtypes[k].itemsize
                                                for k, a in arrays.items()))
            self._buf = {k: np.empty((self.capacity, *np.shape(a)), self.dtypes[k]) for k, a in arrays.items()}
        for k, buf in self._buf.items():
            if np.shape(arrays[k]) != buf.shape[1:]:
                raise ProbeSetError(f"internal: clip {sum(s['n_clips'] for s in self.shards) + self._n} has "
                                    f"{k} of shape {np.shape(arrays[k])}, the set's clips have {buf.shape[1:]}")
            buf[self._n] = arrays[k]
        self._n += 1
        if self._n == self.capacity:
            self.flush()

    def flush(self) -> None:
        """Write the clips buffered so far as one shard (no-op when empty)."""
        if not self._n or self._buf is None:
            return
        rel = f"shards/{len(self.shards):05d}"
        (self.root / rel).mkdir(parents=True)
        for name, buf in self._buf.items():
            path = self.root / rel / f"{name}.npy"
            np.save(path, buf[: self._n], allow_pickle=False)  # a leading slice stays contiguous
            self.files[f"{rel}/{name}.npy"] = sha256_file(path)
        self.shards.append({"path": rel, "n_clips": self._n})
        self._n = 0  # the buffer is reused: every shard of a set has the same clip shape

    @property
    def n_clips(self) -> int:
        return sum(s["n_clips"] for s in self.shards) + self._n


class ShardedArray:
    """One array (``frames``, ``states``, ...) of a set, indexed along clips like an ndarray.

    ``arr[rows]``, ``arr[i]``, ``arr[a:b]`` and ``arr[rows, ...]`` return in-memory copies of just
    those clips; ``np.asarray(arr)`` reads everything (only for small sets).
    """

    def __init__(self, set_dir: Path, name: str, shards: list[tuple[str, int]]) -> None:
        self.set_dir, self.name = Path(set_dir), name
        self.paths = [self.set_dir / rel / f"{name}.npy" if rel else self.set_dir / f"{name}.npy"
                      for rel, _ in shards]
        counts = np.array([n for _, n in shards], dtype=np.int64)
        self.offsets = np.concatenate([[0], np.cumsum(counts)])  # (S + 1,)
        self._open: OrderedDict[int, np.ndarray] = OrderedDict()
        self.shape: tuple[int, ...] = ()
        self.dtype = np.dtype(np.uint8)
        first = self._shard(0)
        self.dtype = first.dtype
        self.shape = (int(self.offsets[-1]), *first.shape[1:])

    def _shard(self, s: int) -> np.ndarray:
        if s in self._open:
            self._open.move_to_end(s)
            return self._open[s]
        path = self.paths[s]
        try:
            arr = np.load(path, mmap_mode="r", allow_pickle=False)
        except (OSError, ValueError) as exc:
            raise ProbeSetError(f"{path} cannot be read: {exc}") from exc
        want = int(self.offsets[s + 1] - self.offsets[s])
        if arr.ndim < 1 or arr.shape[0] != want:
            raise ProbeSetError(f"{path} holds {arr.shape[:1]} clips, the manifest says {want}; "
                                f"the set is damaged, regenerate it")
        if self.shape and (arr.shape[1:] != self.shape[1:] or arr.dtype != self.dtype):
            raise ProbeSetError(f"{path} is {arr.dtype}{arr.shape[1:]} per clip, the set's first shard is "
                                f"{self.dtype}{self.shape[1:]}; the set is damaged, regenerate it")
        self._open[s] = arr
        while len(self._open) > OPEN_SHARDS:  # unmapping gives the pages back
            self._open.popitem(last=False)
        return arr

    def __len__(self) -> int:
        return self.shape[0]

    @property
    def ndim(self) -> int:
        return len(self.shape)

    def read(self, rows: np.ndarray) -> np.ndarray:
        """Clips ``rows`` (any order, repeats allowed) as one in-memory array."""
        rows = np.asarray(rows, dtype=np.int64).reshape(-1)
        if rows.size and (rows.min() < 0 or rows.max() >= len(self)):
            raise IndexError(f"{self.name}: clip rows outside [0, {len(self)})")
        out = np.empty((rows.size, *self.shape[1:]), self.dtype)
        shard = np.searchsorted(self.offsets, rows, side="right") - 1  # (n,)
        for s in np.unique(shard):
            sel = np.flatnonzero(shard == s)
            local = rows[sel] - self.offsets[s]
            order = np.argsort(local, kind="stable")  # ascending reads are page-friendly
            out[sel[order]] = self._shard(int(s))[local[order]]
        return out

    def __getitem__(self, key: Any) -> np.ndarray:
        rest: tuple = ()
        if isinstance(key, tuple):
            key, rest = key[0], key[1:]
        if key is Ellipsis or key is None:  # arr[..., i]: whole array (small sets)
            return np.asarray(self)[(key, *rest)]
        if isinstance(key, (int, np.integer)):
            i = int(key) + (len(self) if key < 0 else 0)
            out = self.read(np.array([i]))[0]
        else:
            if isinstance(key, slice):
                rows = np.arange(len(self))[key]
            else:
                key = np.asarray(key)
                rows = np.flatnonzero(key) if key.dtype == bool else key
            out = self.read(rows)
            rest = (slice(None), *rest) if rest else ()
        return out[rest] if rest else out

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        out = self.read(np.arange(len(self)))
        return out if dtype is None else out.astype(dtype)

    def __getattr__(self, attr: str) -> Any:
        """Other ndarray attributes (``.any()``, ``.sum()``, ...) act on the whole array, read into
        memory: convenient for small sets; large-set code should index chunks of clips instead."""
        if attr.startswith("_") or attr in ("shape", "dtype") or not hasattr(np.ndarray, attr):
            raise AttributeError(attr)
        return getattr(np.asarray(self), attr)

    def __repr__(self) -> str:
        return f"ShardedArray({self.name!r}, shape={self.shape}, dtype={self.dtype}, shards={len(self.paths)})"


def check_shard_paths(shards: Any, where: Path) -> list[tuple[str, int]]:
    """The manifest's shard list as (relative dir, clips); refuses paths outside ``shards/NNNNN``."""
    if not isinstance(shards, list) or not shards:
        raise ProbeSetError(f"{where}: 'shards' must be a non-empty list")
    out = []
    for s in shards:
        rel, n = (s.get("path"), s.get("n_clips")) if isinstance(s, dict) else (None, None)
        if not isinstance(rel, str) or not SHARD_DIR.match(rel) or not isinstance(n, int) or n < 1:
            raise ProbeSetError(f"{where}: bad shard entry {s!r} (expected {{'path': 'shards/NNNNN', "
                                f"'n_clips': n >= 1}})")
        out.append((rel, n))
    return out
