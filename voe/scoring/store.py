"""Write a run directory from per-clip surprise, whoever computed it.

Layout of a run directory::

    frames.parquet  raw per-frame surprise, stored once: clip_id, t, nll (in the run's surprise
                    kind; NaN = not scored)
    clips.parquet   one row per clip: the probe-set index columns (without geometry) plus
                    sum, max, mean_post (mean from the onset on) and n_scored
    run.json        model (or surprise table), surprise kind, order and common-random-number
                    seeds, checkpoint sha256, probe-set manifest sha256 and path, package
                    versions, wall time, launcher, voe version

Why one writer: in-process scoring, sharded scoring and outside surprise tables must give the
same files for the same numbers, so that every metric and report reads them the same way.
"""

from __future__ import annotations

import io
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe import __version__
from voe.errors import ModelContractError
from voe.io import jsonio
from voe.io.atomic import atomic_dir
from voe.io.provenance import package_versions

RUN_SCHEMA_VERSION = 1
#: Index columns copied into ``clips.parquet`` (geometry is bulky and only models need it).
CLIP_COLUMNS = ("clip_id", "concept", "concept_name", "set_id", "set_kind", "variant", "role",
                "onset_frame", "seed", "visible_violation", "n_distractors", "condition", "carries_verdict",
                "balance_claim", "confounded", "params", "row")
SUMMARY_COLUMNS = ("sum", "max", "mean_post", "n_scored")
#: ``run.json`` fields that may differ between runs with identical numbers (how they were run).
VOLATILE_FIELDS = ("wall_time_s", "created_utc", "launcher", "clips_from_cache")
SURPRISE_KINDS = ("nll", "bound", "error")


def surprise_kind(model: Any, given: str | None = None) -> str:
    """The model's declared ``surprise_kind`` (default ``nll``), validated."""
    kind = given if given is not None else getattr(model, "surprise_kind", "nll")
    if kind not in SURPRISE_KINDS:
        name = getattr(model, "name", type(model).__name__) if model is not None else "surprises"
        raise ModelContractError(f"model '{name}': surprise_kind {kind!r} is not one of {SURPRISE_KINDS}")
    return str(kind)


def check_nll(nll: Any, shape: tuple[int, int], model_name: str, clips: tuple[str, ...]) -> np.ndarray:
    """Validate one ``frame_nll`` answer and return it as float64 ``(B, T)``.

    The rule (from ``voe.models.protocol``): the shape is exactly ``(B, T)``; NaN marks frames the
    model does not score and is allowed only in a leading warm-up prefix; every other value is
    finite; each clip has at least one scored frame.

    Args:
        clips: how to name each clip in a message (``key (clip id)``).

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
                                 f"expected (B, T) = {shape} for clips {clips[:3]}...")
    ids = clips or tuple(str(i) for i in range(shape[0]))
    for b, row in enumerate(arr):  # row: (T,)
        if np.isinf(row).any():
            t = int(np.flatnonzero(np.isinf(row))[0])
            raise ModelContractError(f"model '{model_name}': infinite surprise at frame {t} of clip "
                                     f"{ids[b]}; return a finite value (or NaN for unscored warm-up)")
        scored = ~np.isnan(row)
        if not scored.any():
            raise ModelContractError(f"model '{model_name}': clip {ids[b]} has no scored frame (all NaN)")
        first = int(np.argmax(scored))
        if not scored[first:].all():
            t = first + int(np.flatnonzero(~scored[first:])[0])
            raise ModelContractError(f"model '{model_name}': NaN at frame {t} of clip {ids[b]} after "
                                     f"scored frame {first}; NaN is allowed only in a leading warm-up prefix")
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


def assemble(index: pd.DataFrame, by_id: Mapping[str, np.ndarray]) -> tuple[pd.DataFrame, np.ndarray]:
    """Index rows in probe-set order and their surprise ``(N, T)`` from per-clip rows."""
    index = index.sort_values("row").reset_index(drop=True)
    nll = np.stack([np.asarray(by_id[str(c)], dtype=np.float64) for c in index["clip_id"]])  # (N, T)
    return index, nll


def write_run(out: Path, index: pd.DataFrame, nll: np.ndarray, meta: dict[str, Any],
              overwrite: bool = False) -> dict[str, Any]:
    """Write ``frames.parquet``, ``clips.parquet`` and ``run.json`` atomically to ``out``.

    Args:
        index: probe-set index rows in row order, aligned with ``nll`` ``(N, T)``.
        meta: ``run.json`` fields; schema and package versions, creation time and the probe-set
            size are added here.
    """
    N, T = nll.shape
    ids = [str(c) for c in index["clip_id"]]
    clips = index[[c for c in CLIP_COLUMNS if c in index.columns]].copy()
    for key, val in clip_summaries(nll, index["onset_frame"].to_numpy()).items():
        clips[key] = val
    frames = pd.DataFrame({"clip_id": np.repeat(np.asarray(ids, dtype=object), T),
                           "t": np.tile(np.arange(T, dtype=np.int32), N),
                           "nll": nll.reshape(-1)})
    meta = {"schema_version": RUN_SCHEMA_VERSION, "voe_version": __version__, **meta,
            "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "versions": package_versions()}
    meta["probes"] = {**meta["probes"], "n_clips": N, "n_frames": T}
    with atomic_dir(Path(out), overwrite=overwrite) as tmp:
        (tmp / "frames.parquet").write_bytes(_parquet_bytes(frames))
        (tmp / "clips.parquet").write_bytes(_parquet_bytes(clips))
        (tmp / "run.json").write_text(jsonio.dumps(meta, indent=1, sort_keys=True, default=str) + "\n")
    return meta
