"""Sharded clip arrays: written one shard at a time, read a few rows at a time.

Why: a set used to be one stacked ``.npy`` per array, built in memory before writing, so
generating 4,000 clips peaked at 2.1 GB and 100k clips would need about 50 GB. Here clips go
into a preallocated shard buffer as they are made; a full shard is written, hashed and dropped.
Readers read just the rows asked for from a shard's file (after checking its ``.npy`` header:
no pickle, no object arrays), so neither side's memory grows with the number of clips.

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
from pathlib import Path
from typing import Any

import numpy as np

from voe.errors import ProbeSetError
from voe.io.paths import inside
from voe.io.provenance import sha256_file

SHARD_BYTES = 64 << 20  # a shard's four files together stay under about 64 MiB
MAX_SHARD_CLIPS = 256
SHARD_DIR = re.compile(r"^shards/\d{5}$")  # the only shard paths a manifest may name


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
        self._headers: dict[int, tuple[int, tuple[int, ...], np.dtype]] = {}  # headers, not data
        self.shape: tuple[int, ...] = ()
        self.dtype = np.dtype(np.uint8)
        _, shape, self.dtype = self._shard(0)
        self.shape = (int(self.offsets[-1]), *shape[1:])

    def _shard(self, s: int) -> tuple[int, tuple[int, ...], np.dtype]:
        """(data offset, shape, dtype) of shard ``s``'s file, from its ``.npy`` header."""
        if s in self._headers:
            return self._headers[s]
        path = self.paths[s]
        inside(self.set_dir, path.relative_to(self.set_dir), self.set_dir / "manifest.json", ProbeSetError)
        try:
            with open(path, "rb") as fh:
                version = np.lib.format.read_magic(fh)
                shape, fortran, dtype = (np.lib.format.read_array_header_1_0(fh) if version == (1, 0)
                                         else np.lib.format.read_array_header_2_0(fh))
                offset = fh.tell()
        except Exception as exc:  # a damaged header raises ValueError, SyntaxError, TokenError...
            raise ProbeSetError(f"{path} cannot be read: {exc}") from exc
        if fortran or dtype.hasobject:
            raise ProbeSetError(f"{path}: not a C-ordered plain array; regenerate the set")
        want = int(self.offsets[s + 1] - self.offsets[s])
        if len(shape) < 1 or shape[0] != want:
            raise ProbeSetError(f"{path} holds {shape[:1]} clips, the manifest says {want}; "
                                f"the set is damaged, regenerate it")
        if self.shape and (shape[1:] != self.shape[1:] or dtype != self.dtype):
            raise ProbeSetError(f"{path} is {dtype}{shape[1:]} per clip, the set's first shard is "
                                f"{self.dtype}{self.shape[1:]}; the set is damaged, regenerate it")
        self._headers[s] = (offset, shape, dtype)
        return self._headers[s]

    def _read_rows(self, s: int, local: np.ndarray, out: np.ndarray) -> None:
        """Read ascending rows ``local`` of shard ``s`` into ``out`` (len(local), ...), one read per
        run of consecutive rows. Why plain reads, not a memory map: mapped pages count in the
        process's resident memory for as long as the map lives."""
        offset, shape, dtype = self._shard(s)
        row_bytes = int(np.prod(shape[1:], dtype=np.int64)) * dtype.itemsize
        flat = out.reshape(len(local), -1).view(np.uint8)  # (n, row_bytes)
        breaks = np.flatnonzero(np.diff(local) != 1) + 1
        try:
            with open(self.paths[s], "rb", buffering=0) as fh:
                for run in np.split(np.arange(len(local)), breaks):
                    a, n = int(local[run[0]]), len(run)
                    fh.seek(offset + a * row_bytes)
                    got = fh.readinto(memoryview(flat[run[0]:run[0] + n]).cast("B"))
                    if got != n * row_bytes:
                        raise ProbeSetError(f"{self.paths[s]} is truncated; regenerate the set")
        except OSError as exc:
            raise ProbeSetError(f"{self.paths[s]} cannot be read: {exc}") from exc

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
            local, inverse = np.unique(rows[sel] - self.offsets[s], return_inverse=True)  # ascending
            if len(local) == len(sel) and np.all(inverse == np.arange(len(sel))) and np.all(np.diff(sel) == 1):
                self._read_rows(int(s), local, out[sel[0]:sel[-1] + 1])  # in order: straight into ``out``
            else:
                buf = np.empty((len(local), *self.shape[1:]), self.dtype)
                self._read_rows(int(s), local, buf)
                out[sel] = buf[inverse]
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
