"""Probe sets (and training sets) on disk: one directory, no pickle, checksummed.

Layout::

    manifest.json   schema version, package versions, seeds, concept ids, dt, frame size,
                    feature names, and the sha256 of every other file
    index.parquet   one row per clip (clip_id, concept, set_id, variant, role, onset_frame, seed,
                    visible_violation, n_distractors, params JSON, geometry JSON, row, ...)
    frames.npy      (N, T, H, W) uint8
    states.npy      (N, T, K, F) float32, NaN where not present
    present.npy     (N, T, K) bool, visible in that frame
    exists.npy      (N, T, K) bool, exists (ground truth; not shown to models)

Why stacked ``.npy``: they are memory-mapped without pickle, and byte-identical for the same
seed (``np.savez`` would stamp zip times).
"""

from __future__ import annotations

import io
import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe.errors import ProbeSetError
from voe.io.atomic import atomic_dir
from voe.io.batch import Batch
from voe.io.provenance import sha256_bytes, sha256_file

SCHEMA_VERSION = 1
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


def _npy_bytes(arr: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.ascontiguousarray(arr), allow_pickle=False)
    return buf.getvalue()


def _parquet_bytes(df: pd.DataFrame) -> bytes:
    buf = io.BytesIO()
    df.to_parquet(buf, index=False, engine="pyarrow", compression="zstd")
    return buf.getvalue()


def write_probe_set(out: Path, records: Iterable[ClipRecord], meta: dict[str, Any],
                    overwrite: bool = False) -> dict[str, Any]:
    """Write clips and a manifest to ``out`` atomically; returns the manifest.

    Args:
        out: target directory (must not exist or be empty unless ``overwrite``).
        records: clips in their final order.
        meta: manifest fields (seeds, concept ids, dt, size, feature names, versions, ...).
    """
    records = list(records)
    if not records:
        raise ProbeSetError(f"refusing to write an empty set to {out}")
    rows = []
    for i, rec in enumerate(records):
        row = dict(rec.row)
        row["row"] = i
        rows.append(row)
    index = pd.DataFrame(rows)
    missing = [c for c in INDEX_COLUMNS if c not in index.columns]
    if missing:
        raise ProbeSetError(f"internal: index rows lack columns {missing}")
    blobs = {
        "index.parquet": _parquet_bytes(index),
        "frames.npy": _npy_bytes(np.stack([r.frames for r in records]).astype(np.uint8)),
        "states.npy": _npy_bytes(np.stack([r.states for r in records]).astype(np.float32)),
        "present.npy": _npy_bytes(np.stack([r.present for r in records]).astype(bool)),
        "exists.npy": _npy_bytes(np.stack([r.exists for r in records]).astype(bool)),
    }
    manifest = {"schema_version": SCHEMA_VERSION, **meta, "n_clips": len(records),
                "files": {name: sha256_bytes(data) for name, data in sorted(blobs.items())}}
    with atomic_dir(Path(out), overwrite=overwrite) as tmp:
        for name, data in blobs.items():
            (tmp / name).write_bytes(data)
        (tmp / "manifest.json").write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
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
        try:
            self.manifest: dict[str, Any] = json.loads(mpath.read_text())
        except json.JSONDecodeError as exc:
            raise ProbeSetError(f"{mpath} is not valid JSON: {exc}") from exc
        if self.manifest.get("schema_version") != SCHEMA_VERSION:
            raise ProbeSetError(f"{mpath}: schema_version {self.manifest.get('schema_version')!r} "
                                f"is not {SCHEMA_VERSION}")
        try:
            self.index: pd.DataFrame = pd.read_parquet(self.path / "index.parquet")
        except Exception as exc:  # pyarrow raises several types for corrupt files
            raise ProbeSetError(f"{self.path / 'index.parquet'} cannot be read: {exc}") from exc
        missing = [c for c in INDEX_COLUMNS if c not in self.index.columns]
        if missing:
            raise ProbeSetError(f"{self.path / 'index.parquet'} lacks columns {missing}")
        self._arrays: dict[str, np.ndarray] = {}
        self._rows = pd.Series(self.index["row"].to_numpy(), index=self.index["clip_id"].to_numpy())

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

    def array(self, name: str) -> np.ndarray:
        """A memory-mapped stacked array (``frames``, ``states``, ``present`` or ``exists``)."""
        if name not in self._arrays:
            path = self.path / f"{name}.npy"
            try:
                self._arrays[name] = np.load(path, mmap_mode="r", allow_pickle=False)
            except (OSError, ValueError) as exc:
                raise ProbeSetError(f"{path} cannot be read: {exc}") from exc
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
        return {name: np.asarray(self.array(name)[rows]) for name in ARRAYS}

    def batch(self, clip_ids: Sequence[str]) -> Batch:
        """The model-facing ``Batch`` for clips (no ground-truth ``exists``)."""
        rows = self.rows(clip_ids)
        geo = self.index.set_index("clip_id").loc[list(clip_ids), "geometry"]
        return Batch(
            frames=np.asarray(self.array("frames")[rows]),
            states=np.asarray(self.array("states")[rows]),
            present=np.asarray(self.array("present")[rows]),
            feature_names=self.feature_names, dt=self.dt,
            geometry=tuple(json.loads(g) for g in geo), clip_ids=tuple(clip_ids),
        )

    def __len__(self) -> int:
        return len(self.index)

    def __repr__(self) -> str:
        return f"ProbeSet({str(self.path)!r}, clips={len(self)}, kind={self.manifest.get('kind')!r})"


def load_probe_set(path: str | Path) -> ProbeSet:
    """Open a probe set or training set directory written by ``voe probes generate``."""
    return ProbeSet(Path(path))
