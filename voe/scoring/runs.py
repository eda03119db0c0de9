"""Read stored runs (``voe score`` output) back, checking they are complete and comparable.

Why: every metric and report is computed from these files; a run with a missing column, no clips,
or from another probe set must be refused loudly, never silently compared.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe.errors import RunError
from voe.io.paths import inside, resolve_ref
from voe.scoring.runcheck import check_clips, check_frames

#: What a run's surprise is, by ``surprise_kind`` (``run.json``; runs before it are ``nll``).
SURPRISE_UNITS = {"nll": "nats", "bound": "bound", "error": "error"}
SURPRISE_MEANING = {
    "nll": "exact negative log-likelihood of each frame given the past, in nats",
    "bound": "a bound on it (an ELBO or denoising loss), not calibrated nats",
    "error": "a prediction error in some representation space, unitless",
}
CLIP_REQUIRED = ("clip_id", "concept", "set_id", "set_kind", "variant", "role", "onset_frame",
                 "visible_violation", "n_distractors", "sum", "max", "mean_post", "n_scored")
FRAME_REQUIRED = ("clip_id", "t", "nll")


@dataclass
class Run:
    """One stored run.

    Attributes:
        path: the run directory.
        meta: parsed ``run.json``.
        clips: one row per clip (``clips.parquet``), in probe-set row order.
        nll: ``(N, T)`` per-frame surprise, rows aligned with ``clips``; NaN = not scored.
        label: the model's display name (made unique by ``load_runs``).
    """

    path: Path
    meta: dict[str, Any]
    clips: pd.DataFrame
    nll: np.ndarray
    label: str

    @property
    def manifest_sha256(self) -> str:
        return str(self.meta["probes"]["manifest_sha256"])

    @property
    def surprise_kind(self) -> str:
        """``nll``, ``bound`` or ``error``: only ``nll`` is in calibrated nats."""
        return str(self.meta.get("surprise_kind", "nll"))

    @property
    def unit(self) -> str:
        return SURPRISE_UNITS.get(self.surprise_kind, self.surprise_kind)

    @property
    def probes_path(self) -> Path:
        """The scored probe set: recorded relative to the run directory (or absolute, older runs).

        Not confined to the run directory: it names another input, which is only used after its
        manifest sha256 matches the one recorded here.
        """
        return resolve_ref(self.meta["probes"]["path"], self.path)


def _read_parquet(path: Path, required: Sequence[str]) -> pd.DataFrame:
    if not path.exists():
        raise RunError(f"{path} is missing; is {path.parent} a run written by `voe score`?")
    try:
        df = pd.read_parquet(path)
    except Exception as exc:  # pyarrow raises several types for corrupt files
        raise RunError(f"{path} cannot be read: {exc}") from exc
    missing = [c for c in required if c not in df.columns]
    if missing:
        raise RunError(f"{path} lacks column(s) {missing}; re-score with `voe score`")
    if df.empty:
        raise RunError(f"{path} is empty (no clips scored); re-score with `voe score`")
    return df


def load_run(path: str | Path) -> Run:
    """Open one run directory; raises ``RunError`` if anything is missing or inconsistent."""
    path = Path(path)
    if not path.is_dir():
        raise RunError(f"run directory {path} does not exist")
    mpath = path / "run.json"
    if not mpath.exists():
        raise RunError(f"{mpath} is missing; is {path} a run written by `voe score`?")
    try:
        meta = json.loads(inside(path, "run.json", path, RunError).read_text())
        _ = meta["probes"]["manifest_sha256"], meta["model"]["name"], meta["probes"]["path"]
        if not all(isinstance(v, str) for v in (meta["probes"]["manifest_sha256"], meta["probes"]["path"])):
            raise TypeError("probes.path and probes.manifest_sha256 must be strings")
        if not isinstance(meta["model"]["name"], str) or not isinstance(meta.get("surprise_kind", "nll"), str):
            raise TypeError("model.name and surprise_kind must be strings")
    except (json.JSONDecodeError, UnicodeDecodeError, KeyError, TypeError) as exc:
        raise RunError(f"{mpath} is malformed ({exc!r}); re-score with `voe score`") from exc
    clips = _read_parquet(inside(path, "clips.parquet", mpath, RunError), CLIP_REQUIRED).reset_index(drop=True)
    frames = _read_parquet(inside(path, "frames.parquet", mpath, RunError), FRAME_REQUIRED)
    check_clips(clips, path / "clips.parquet")
    check_frames(frames, path / "frames.parquet")
    T = int(frames["t"].max()) + 1
    pos = pd.Series(np.arange(len(clips)), index=clips["clip_id"].to_numpy())
    try:
        rows = pos.loc[frames["clip_id"].to_numpy()].to_numpy()
    except KeyError as exc:
        raise RunError(f"{path}: frames.parquet names clips absent from clips.parquet: {exc}") from exc
    nll = np.full((len(clips), T), np.nan)  # (N, T)
    nll[rows, frames["t"].to_numpy()] = frames["nll"].to_numpy(dtype=np.float64)
    counts = np.bincount(rows, minlength=len(clips))
    if (counts != T).any():
        bad = clips["clip_id"].iloc[int(np.flatnonzero(counts != T)[0])]
        raise RunError(f"{path}: clip '{bad}' has {counts[clips['clip_id'] == bad].sum()} frames "
                       f"in frames.parquet, expected {T}")
    return Run(path, meta, clips, nll, str(meta["model"]["name"]))


def load_runs(paths: Sequence[str | Path]) -> list[Run]:
    """Open several runs of the same probe set; labels are made unique.

    Raises:
        RunError: no runs, or runs scored on different probe sets (manifest sha256 differ).
    """
    if not paths:
        raise RunError("no run directories given")
    runs = [load_run(p) for p in paths]
    ref = runs[0]
    for run in runs[1:]:
        if run.manifest_sha256 != ref.manifest_sha256:
            raise RunError(
                f"runs come from different probe sets: {ref.path} scored {ref.probes_path} "
                f"(manifest {ref.manifest_sha256[:12]}), {run.path} scored {run.probes_path} "
                f"(manifest {run.manifest_sha256[:12]}); score every model on the same probe set")
    names = [r.label for r in runs]
    for run in runs:
        if names.count(run.label) > 1:
            run.label = f"{run.label} ({run.path.name})"
    return runs
