"""Score a model on every clip of a probe set (teacher-forced) and store the run on disk.

Layout of a run directory::

    frames.parquet  raw per-frame surprise, stored once: clip_id, t, nll (nats; NaN = not scored)
    clips.parquet   one row per clip: the probe-set index columns (without geometry) plus
                    sum, max, mean_post (mean from the onset on) and n_scored
    run.json        model ref, args, name, observation, checkpoint sha256, probe-set manifest
                    sha256 and path, package versions, wall time, voe version

Why teacher forcing only: ``frame_nll`` is given the stored clip and returns
``-log p(o_t | o_<t)`` for every frame, so there is nothing to roll out; every metric is then a
function of these numbers alone.
"""

from __future__ import annotations

import io
import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe import __version__
from voe.errors import ModelContractError
from voe.io.atomic import atomic_dir
from voe.io.paths import portable_ref
from voe.io.probeset import ProbeSet, load_probe_set
from voe.io.provenance import package_versions, sha256_path

RUN_SCHEMA_VERSION = 1
#: Index columns copied into ``clips.parquet`` (geometry is bulky and only models need it).
CLIP_COLUMNS = ("clip_id", "concept", "concept_name", "set_id", "set_kind", "variant", "role",
                "onset_frame", "seed", "visible_violation", "n_distractors", "params", "row")
SUMMARY_COLUMNS = ("sum", "max", "mean_post", "n_scored")


def check_nll(nll: Any, shape: tuple[int, int], model_name: str, clip_ids: tuple[str, ...]) -> np.ndarray:
    """Validate one ``frame_nll`` answer and return it as float64 ``(B, T)``.

    The rule (from ``voe.models.protocol``): the shape is exactly ``(B, T)``; NaN marks frames the
    model does not score and is allowed only in a leading warm-up prefix; every other value is
    finite; each clip has at least one scored frame.

    Raises:
        ModelContractError: naming the model and the first offending clip.
    """
    try:
        arr = np.asarray(nll, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ModelContractError(f"model '{model_name}': frame_nll returned {type(nll).__name__}, "
                                 f"not a numeric (B, T) array: {exc}") from exc
    if arr.shape != shape:
        raise ModelContractError(f"model '{model_name}': frame_nll returned shape {arr.shape}, "
                                 f"expected (B, T) = {shape} for clips {clip_ids[:3]}...")
    ids = clip_ids or tuple(str(i) for i in range(shape[0]))
    for b, row in enumerate(arr):  # row: (T,)
        if np.isinf(row).any():
            t = int(np.flatnonzero(np.isinf(row))[0])
            raise ModelContractError(f"model '{model_name}': infinite surprise at frame {t} of clip "
                                     f"'{ids[b]}'; return a finite value (or NaN for unscored warm-up)")
        scored = ~np.isnan(row)
        if not scored.any():
            raise ModelContractError(f"model '{model_name}': clip '{ids[b]}' has no scored frame "
                                     "(all NaN)")
        first = int(np.argmax(scored))
        if not scored[first:].all():
            t = first + int(np.flatnonzero(~scored[first:])[0])
            raise ModelContractError(f"model '{model_name}': NaN at frame {t} of clip '{ids[b]}' "
                                     f"after scored frame {first}; NaN is allowed only in a leading "
                                     "warm-up prefix")
    return arr


def clip_summaries(nll: np.ndarray, onset: np.ndarray) -> dict[str, np.ndarray]:
    """Per-clip ``sum``, ``max``, ``mean_post`` and ``n_scored`` of ``nll`` ``(N, T)``."""
    scored = ~np.isnan(nll)  # (N, T)
    post = scored & (np.arange(nll.shape[1])[None, :] >= onset[:, None])  # (N, T)
    n_post = post.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean_post = np.where(n_post > 0, np.where(post, nll, 0.0).sum(axis=1) / n_post, np.nan)
    return {"sum": np.where(scored, nll, 0.0).sum(axis=1),
            "max": np.where(scored, nll, -np.inf).max(axis=1),
            "mean_post": mean_post, "n_scored": scored.sum(axis=1).astype(np.int64)}


def _parquet_bytes(df: pd.DataFrame) -> bytes:
    buf = io.BytesIO()
    df.to_parquet(buf, index=False, engine="pyarrow", compression="zstd")
    return buf.getvalue()


def score_probe_set(model: Any, probes: ProbeSet | str | Path, out: Path, *, model_ref: str | None = None,
                    model_args: dict[str, Any] | None = None, checkpoint: Path | None = None,
                    batch_size: int = 16, overwrite: bool = False,
                    progress: Callable[[int], None] | None = None) -> dict[str, Any]:
    """Run ``model.frame_nll`` over every clip of ``probes`` and write a run directory to ``out``.

    Args:
        model: anything following ``voe.models.protocol.Model``.
        probes: a probe set or its directory.
        out: the run directory, written atomically (must be new or empty unless ``overwrite``).
        model_ref, model_args, checkpoint: how the model was made, recorded in ``run.json``.
        batch_size: clips per ``frame_nll`` call.
        progress: called with the number of clips done after each batch.

    Returns:
        The ``run.json`` contents.
    """
    ps = probes if isinstance(probes, ProbeSet) else load_probe_set(probes)
    if batch_size < 1:
        raise ValueError("batch_size must be >= 1")
    name = str(getattr(model, "name", type(model).__name__))
    index = ps.index.sort_values("row").reset_index(drop=True)
    ids = [str(c) for c in index["clip_id"]]
    t0 = time.perf_counter()
    chunks = []
    for start in range(0, len(ids), batch_size):
        batch = ps.batch(ids[start:start + batch_size])
        chunks.append(check_nll(model.frame_nll(batch), batch.shape, name, batch.clip_ids))
        if progress:
            progress(len(batch))
    wall = time.perf_counter() - t0
    nll = np.concatenate(chunks, axis=0)  # (N, T)
    N, T = nll.shape

    clips = index[[c for c in CLIP_COLUMNS if c in index.columns]].copy()
    for key, val in clip_summaries(nll, index["onset_frame"].to_numpy()).items():
        clips[key] = val
    frames = pd.DataFrame({"clip_id": np.repeat(np.asarray(ids, dtype=object), T),
                           "t": np.tile(np.arange(T, dtype=np.int32), N),
                           "nll": nll.reshape(-1)})
    meta = {
        "schema_version": RUN_SCHEMA_VERSION, "voe_version": __version__,
        "model": {"ref": model_ref or f"{type(model).__module__}:{type(model).__qualname__}",
                  "class": f"{type(model).__module__}:{type(model).__qualname__}",
                  "args": dict(model_args or {}), "name": name,
                  "observation": str(getattr(model, "observation", "")),
                  "checkpoint": portable_ref(checkpoint, out) if checkpoint else None,
                  "checkpoint_sha256": sha256_path(Path(checkpoint)) if checkpoint else None},
        "probes": {"path": portable_ref(ps.path, out), "manifest_sha256": ps.manifest_sha256,
                   "concepts": list(ps.manifest.get("concepts", [])), "n_clips": N, "n_frames": T},
        "batch_size": batch_size, "wall_time_s": round(wall, 3),
        "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "versions": package_versions(),
    }
    with atomic_dir(Path(out), overwrite=overwrite) as tmp:
        (tmp / "frames.parquet").write_bytes(_parquet_bytes(frames))
        (tmp / "clips.parquet").write_bytes(_parquet_bytes(clips))
        (tmp / "run.json").write_text(json.dumps(meta, indent=1, sort_keys=True, default=str) + "\n")
    return meta
