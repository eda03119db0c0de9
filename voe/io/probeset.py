"""Probe sets (and training sets) on disk: one directory, no pickle, checksummed, sharded.

Layout::

    manifest.json   schema version, package versions, seeds, concept ids, dt, frame size,
                    feature names, the shards and their clip counts, and the sha256 of every
                    other file
    index.parquet   one row per clip (clip_id, concept, set_id, variant, role, onset_frame, seed,
                    visible_violation, n_distractors, params JSON, geometry JSON, row, ...)
    shards/NNNNN/   frames.npy (n, T, H, W) uint8; states.npy (n, T, K, F) float32, NaN where
                    not present; present.npy (n, T, K) bool, visible in that frame;
                    exists.npy (n, T, K) bool, exists (ground truth; not shown to models)

``row`` numbers clips across shards in order (see ``voe.io.shards``). Why stacked ``.npy`` per
shard: they are memory-mapped without pickle, byte-identical for the same seed (``np.savez``
would stamp zip times), and neither writing nor reading a set holds more than a shard or two.
Sets written before sharding (schema 1: the four arrays at the top level) are still read.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe.errors import ProbeSetError
from voe.io import jsonio
from voe.io.atomic import atomic_dir
from voe.io.batch import Batch
from voe.io.paths import inside
from voe.io.provenance import sha256_bytes, sha256_file
from voe.io.schema import check_index, check_manifest
from voe.io.shards import ShardedArray, ShardWriter, check_shard_paths

SCHEMA_VERSION = 2  # 2: sharded arrays; 1: one stacked array per name (read, never written)
READABLE_SCHEMAS = (1, 2)
DTYPES = {"frames": np.uint8, "states": np.float32, "present": bool, "exists": bool}
ARRAYS = ("frames", "states", "present", "exists")
INDEX_COLUMNS = ("clip_id", "concept", "set_id", "variant", "role", "onset_frame", "seed",
                 "visible_violation", "n_distractors", "params", "geometry", "row")
ROLES = ("possible", "impossible", "train")


@dataclass
class ClipRecord:
    """One clip to be written: its index row (without ``row``) and its arrays."""

    row: dict[str, Any]
    frames: np.ndarray  # (T, H, W) uint8
    states: np.ndarray  # (T, K, F) float32
    present: np.ndarray  # (T, K) bool
    exists: np.ndarray  # (T, K) bool


def write_probe_set(out: Path, records: Iterable[ClipRecord], meta: dict[str, Any],
                    overwrite: bool = False) -> dict[str, Any]:
    """Write clips and a manifest to ``out`` atomically; returns the manifest.

    Records are consumed one at a time and written a shard at a time, so a generator of clips
    is never held in memory as a whole (only the index rows are).

    Args:
        out: target directory (must not exist or be empty unless ``overwrite``).
        records: clips in their final order (any iterable, e.g. ``parallel_map``'s iterator).
        meta: manifest fields (seeds, concept ids, dt, size, feature names, versions, ...).
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    tables: list[pa.Table] = []  # index rows, 256 at a time in columnar form (compact)
    rows: list[dict[str, Any]] = []
    with atomic_dir(Path(out), overwrite=overwrite) as tmp:
        writer = ShardWriter(tmp, DTYPES)
        for i, rec in enumerate(records):
            rows.append({**rec.row, "row": i})
            writer.add({name: getattr(rec, name) for name in ARRAYS})
            if len(rows) == 256:
                tables.append(pa.Table.from_pylist(rows))
                rows = []
        writer.flush()
        if rows:
            tables.append(pa.Table.from_pylist(rows))
        if not tables:
            raise ProbeSetError(f"refusing to write an empty set to {out}")
        index = pa.concat_tables(tables, promote_options="permissive")  # null -> str, int -> float
        del tables
        missing = [c for c in INDEX_COLUMNS if c not in index.column_names]
        if missing:
            raise ProbeSetError(f"internal: index rows lack columns {missing}")
        buf = pa.BufferOutputStream()
        pq.write_table(index, buf, compression="zstd")
        blob = buf.getvalue().to_pybytes()
        (tmp / "index.parquet").write_bytes(blob)
        files = {"index.parquet": sha256_bytes(blob), **writer.files}
        manifest = {"schema_version": SCHEMA_VERSION, **meta, "n_clips": index.num_rows,
                    "shard_clips": writer.capacity, "shards": writer.shards,
                    "files": dict(sorted(files.items()))}
        (tmp / "manifest.json").write_text(jsonio.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest


class ProbeSet:
    """A probe or training set opened from disk (arrays memory-mapped, never unpickled).

    Attributes:
        path: the directory.
        manifest: parsed ``manifest.json``.
        index: one row per clip (pandas DataFrame).
    """

    def __init__(self, path: Path) -> None:
        self.path = Path(path)
        if not self.path.is_dir():
            raise ProbeSetError(f"probe set {self.path} does not exist or is not a directory")
        mpath = self.path / "manifest.json"
        if not mpath.exists():
            raise ProbeSetError(f"{mpath} is missing; is {self.path} a voe probe set?")
        inside(self.path, "manifest.json", self.path, ProbeSetError)  # not a symlink leading out
        try:
            self.manifest: dict[str, Any] = json.loads(mpath.read_text())
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise ProbeSetError(f"{mpath} is not valid JSON: {exc}") from exc
        if not isinstance(self.manifest, dict):
            raise ProbeSetError(f"{mpath} is not a JSON object")
        version = self.manifest.get("schema_version")
        if version not in READABLE_SCHEMAS:
            raise ProbeSetError(f"{mpath}: schema_version {version!r} is not one of {READABLE_SCHEMAS}; "
                                f"regenerate the set with this voe (or upgrade voe)")
        files = self.manifest.get("files", {})
        if not isinstance(files, dict):
            raise ProbeSetError(f"{mpath}: 'files' must map file names to sha256")
        for name in files:  # every listed file stays inside the set, symlinks included
            inside(self.path, name, mpath, ProbeSetError)
        check_manifest(self.manifest, mpath)
        ipath = inside(self.path, "index.parquet", mpath, ProbeSetError)
        try:
            self.index: pd.DataFrame = pd.read_parquet(ipath)
        except Exception as exc:  # pyarrow raises several types for corrupt files
            raise ProbeSetError(f"{self.path / 'index.parquet'} cannot be read: {exc}") from exc
        missing = [c for c in INDEX_COLUMNS if c not in self.index.columns]
        if missing:
            raise ProbeSetError(f"{self.path / 'index.parquet'} lacks columns {missing}")
        if version == 1:  # one stacked array per name at the top level: a single "shard"
            self._shards = [("", int(self.manifest.get("n_clips", len(self.index))))]
        else:
            self._shards = check_shard_paths(self.manifest.get("shards"), mpath)
        check_index(self.index, ipath, sum(n for _, n in self._shards))
        self._arrays: dict[str, ShardedArray] = {}
        ids = self.index["clip_id"].to_numpy()
        self._rows = pd.Series(self.index["row"].to_numpy(), index=ids)
        self._pos = pd.Series(np.arange(len(ids)), index=ids)  # position in ``index``

    # -- metadata ----------------------------------------------------------------------------
    @property
    def feature_names(self) -> tuple[str, ...]:
        return tuple(self.manifest["feature_names"])

    @property
    def dt(self) -> float:
        return float(self.manifest["dt"])

    @property
    def manifest_sha256(self) -> str:
        """Hash of the manifest, which pins every file by its own hash."""
        return sha256_file(self.path / "manifest.json")

    @property
    def shards(self) -> list[tuple[str, int]]:
        """(directory relative to the set, number of clips) per shard, in row order."""
        return list(self._shards)

    def data_files(self) -> list[str]:
        """Relative paths of every array file the set must have (what the manifest hashes)."""
        return [f"{rel}/{a}.npy" if rel else f"{a}.npy" for rel, _ in self._shards for a in ARRAYS]

    def shard_of(self, rows: np.ndarray) -> np.ndarray:
        """The shard number of each clip row."""
        ends = np.cumsum([n for _, n in self._shards])
        return np.searchsorted(ends, np.asarray(rows), side="right")

    def array(self, name: str) -> ShardedArray:
        """A clip-indexed view of one array (``frames``, ``states``, ``present`` or ``exists``):
        ``arr[rows]`` reads just those clips from their shards."""
        if name not in ARRAYS:
            raise ProbeSetError(f"unknown array '{name}' (known: {', '.join(ARRAYS)})")
        if name not in self._arrays:
            self._arrays[name] = ShardedArray(self.path, name, self._shards)
        return self._arrays[name]

    def rows(self, clip_ids: Sequence[str]) -> np.ndarray:
        try:
            return self._rows.loc[list(clip_ids)].to_numpy()
        except KeyError as exc:
            raise ProbeSetError(f"{self.path}: unknown clip id(s) {exc}") from exc

    # -- data --------------------------------------------------------------------------------
    def get(self, clip_ids: Sequence[str]) -> dict[str, np.ndarray]:
        """Frames ``(B,T,H,W)``, states ``(B,T,K,F)``, present/exists ``(B,T,K)`` for clips."""
        rows = self.rows(clip_ids)
        return {name: self.array(name).read(rows) for name in ARRAYS}

    def batch(self, clip_ids: Sequence[str]) -> Batch:
        """The model-facing ``Batch`` for clips (no ground-truth ``exists``)."""
        rows = self.rows(clip_ids)
        geo = self.index["geometry"].to_numpy()[self._pos.loc[list(clip_ids)].to_numpy()]
        return Batch(
            frames=self.array("frames").read(rows),
            states=self.array("states").read(rows),
            present=self.array("present").read(rows),
            feature_names=self.feature_names, dt=self.dt,
            geometry=tuple(self._geometry(g) for g in geo), clip_ids=tuple(clip_ids),
        )

    def _geometry(self, text: str) -> dict[str, Any]:
        try:
            geo = json.loads(text)
        except (json.JSONDecodeError, TypeError) as exc:
            raise ProbeSetError(f"{self.path / 'index.parquet'}: geometry is not valid JSON ({exc})") from exc
        if not isinstance(geo, dict):
            raise ProbeSetError(f"{self.path / 'index.parquet'}: geometry must be a JSON object")
        return geo

    def batches(self, clip_ids: Sequence[str], size: int = 64) -> Iterator[Batch]:
        """``batch`` over consecutive chunks of ``clip_ids``: a bounded amount in memory at once."""
        ids = list(clip_ids)
        for start in range(0, len(ids), size):
            yield self.batch(ids[start:start + size])

    def __len__(self) -> int:
        return len(self.index)

    def __repr__(self) -> str:
        return f"ProbeSet({str(self.path)!r}, clips={len(self)}, kind={self.manifest.get('kind')!r})"


def load_probe_set(path: str | Path) -> ProbeSet:
    """Open a probe set or training set directory written by ``voe probes generate``."""
    return ProbeSet(Path(path))
