"""A resumable per-clip cache of computed surprise, so an interrupted run picks up where it stopped.

Why: scoring a video model on a large probe set takes hours; a crash, a pre-empted SLURM job, a
model that raises on clip 9,000, or Ctrl-C must not throw away what was computed. Every batch's
per-clip surprise is written (atomically) as soon as it is known. A rerun with the same model,
checkpoint, probe set and scorer config finds the same cache directory and scores only what is
missing. Ranks of a sharded run write their own batches here and rank 0 merges them.

Layout: ``ROOT/<key>/key.json`` (what the key hashes, for humans) and one
``batch-NNNNNN.npz`` per scored batch with ``keys`` (opaque clip keys, unicode) and ``nll``
``(B, T)`` float64, read back with ``allow_pickle=False``. A batch is the unit because a clip's
numbers may depend (in the last bits) on its batch-mates; the schedule is fixed by the key, so
a rerun rebuilds exactly the same batches.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import inspect
import io
import json
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from voe.io import jsonio
from voe.io.atomic import atomic_write_bytes, atomic_write_text

CACHE_SCHEMA = 1


def default_root() -> Path:
    """``$XDG_CACHE_HOME/voe/score`` (``~/.cache/voe/score`` if unset)."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "voe" / "score"


def cache_key(fields: dict[str, Any]) -> str:
    """16 hex characters identifying a model + checkpoint + probe set + scorer config."""
    text = json.dumps({"schema": CACHE_SCHEMA, **fields}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@functools.cache
def _package() -> str:
    """``voe.io.outputs.code_fingerprint`` of the installed package, once per process."""
    from voe.io.outputs import code_fingerprint

    return code_fingerprint()


def code_sha256(model: Any) -> str:
    """A fingerprint of the code that computes ``model``'s surprise.

    Why: the version string does not change while a developer (or a user with an editable
    install) edits a scorer, so a resumed run would otherwise mix surprise computed by old and
    new code. The key covers the whole ``voe`` package (``voe.io.outputs.code_fingerprint``, as
    scratch directories do: built-in models share heads and frame costs across files) and, for a
    model defined outside it, the source file of its class.

    Args:
        model: the scorer being run.

    Returns:
        64 hex characters.
    """
    return class_code_sha256(type(model))


def class_code_sha256(cls: type) -> str:
    """``code_sha256`` of any instance of ``cls`` (lets a stored run be checked against today's
    code without building its model)."""
    h = hashlib.sha256(_package().encode())
    try:
        src = inspect.getsourcefile(cls)
    except TypeError:  # a builtin or C-extension class has no source file
        src = None
    if src and Path(src).is_file():
        h.update(Path(src).read_bytes())
    return h.hexdigest()


class ScoreCache:
    """Per-batch surprise files under ``root/<cache_key(fields)>``.

    Args:
        root: the cache root (``default_root()`` or ``--cache``).
        fields: model ref and args, checkpoint sha256, probe-set manifest sha256, batch size,
            seed, surprise kind, device, precision and the code fingerprint (``code_sha256``):
            whatever could change a number.
    """

    def __init__(self, root: Path, fields: dict[str, Any]) -> None:
        self.dir = Path(root) / cache_key(fields)
        self.fields = fields
        self.dir.mkdir(parents=True, exist_ok=True)
        info = self.dir / "key.json"
        if not info.exists():
            atomic_write_text(info, jsonio.dumps(fields, indent=1, sort_keys=True, default=str) + "\n")

    def _path(self, i: int) -> Path:
        return self.dir / f"batch-{i:06d}.npz"

    def put(self, i: int, keys: tuple[str, ...], nll: np.ndarray) -> None:
        """Store batch ``i``'s surprise ``(B, T)`` for clips ``keys`` (atomic)."""
        buf = io.BytesIO()
        np.savez(buf, keys=np.asarray(keys, dtype="U"), nll=np.asarray(nll, dtype=np.float64))
        atomic_write_bytes(self._path(i), buf.getvalue())

    def get(self, i: int, keys: tuple[str, ...]) -> np.ndarray | None:
        """Batch ``i``'s stored surprise ``(B, T)``, or None if absent, unreadable or for other clips."""
        path = self._path(i)
        if not path.exists():
            return None
        try:
            with np.load(path, allow_pickle=False) as z:
                stored, nll = tuple(str(k) for k in z["keys"]), np.array(z["nll"], dtype=np.float64)
        except (OSError, ValueError, KeyError):
            return None  # a damaged entry is recomputed, never trusted
        return nll if stored == tuple(keys) and nll.ndim == 2 and len(nll) == len(keys) else None

    def __len__(self) -> int:
        return sum(1 for _ in self.dir.glob("batch-*.npz"))

    def clear(self) -> None:
        """Remove this key's directory (after the run it served is written)."""
        with contextlib.suppress(FileNotFoundError):
            shutil.rmtree(self.dir)
