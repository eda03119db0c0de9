"""Types and consistency of a stored run's tables, checked when the run is opened.

Why: reports, tables and metrics index these columns without looking. A ``frames.parquet`` whose
``t`` holds floats, a duplicated frame, or a matched set left with only possible clips used to end
in an ``IndexError`` or ``ValueError`` traceback inside the metrics. Fuzzing found each check
below; every problem raises one ``RunError`` naming the file and the column.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from voe.errors import RunError

MAX_FRAMES = 100_000
ROLES = ("possible", "impossible")
#: Set-level columns (``voe.scoring.table`` groups clips into sets by these).
SET_COLUMNS = ("concept", "set_kind", "visible_violation", "n_distractors", "condition", "carries_verdict",
               "confounded")


def _text(df: pd.DataFrame, col: str, path: Path) -> None:
    try:
        vals = df[col].to_numpy()
    except Exception as exc:  # noqa: BLE001 - pyarrow strings that are not UTF-8 fail on conversion
        raise RunError(f"{path}: column '{col}' is not valid text ({exc})") from exc
    bad = [i for i, v in enumerate(vals) if not isinstance(v, str)]
    if bad:
        raise RunError(f"{path}: column '{col}' must hold text; row {bad[0]} has {vals[bad[0]]!r:.60}")


def _integers(df: pd.DataFrame, col: str, path: Path, lo: int = 0, hi: int = 2**31) -> None:
    s = df[col]
    if not pd.api.types.is_integer_dtype(s) or pd.api.types.is_bool_dtype(s):
        raise RunError(f"{path}: column '{col}' must hold integers, not {s.dtype}")
    v = s.to_numpy()
    if ((v < lo) | (v >= hi)).any():
        row = int(np.flatnonzero((v < lo) | (v >= hi))[0])
        raise RunError(f"{path}: column '{col}' has {v[row]} in row {row}, outside {lo}..{hi - 1}")


def _numbers(df: pd.DataFrame, col: str, path: Path) -> None:
    s = df[col]
    if not pd.api.types.is_numeric_dtype(s) or pd.api.types.is_bool_dtype(s):
        raise RunError(f"{path}: column '{col}' must hold numbers, not {s.dtype}")


def check_frames(frames: pd.DataFrame, path: Path) -> None:
    """``clip_id`` text, ``t`` a frame number, ``nll`` numbers, each (clip, t) once."""
    _text(frames, "clip_id", path)
    _integers(frames, "t", path, 0, MAX_FRAMES)
    _numbers(frames, "nll", path)
    dup = frames.duplicated(["clip_id", "t"]).to_numpy()
    if dup.any():
        row = int(np.flatnonzero(dup)[0])
        raise RunError(f"{path}: frame {frames['t'].iloc[row]} of clip {frames['clip_id'].iloc[row]!r} "
                       f"appears more than once")


def check_clips(clips: pd.DataFrame, path: Path) -> None:
    """Text and number columns, unique clips, and matched sets with both kinds of clip."""
    for col in ("clip_id", "concept", "set_id", "set_kind", "variant", "role"):
        _text(clips, col, path)
    for col in ("onset_frame", "n_distractors", "n_scored"):
        _integers(clips, col, path, 0 if col != "onset_frame" else -MAX_FRAMES, MAX_FRAMES)
    for col in ("sum", "max", "mean_post"):
        _numbers(clips, col, path)
    vv = clips["visible_violation"]
    if not (pd.api.types.is_bool_dtype(vv) or pd.api.types.is_integer_dtype(vv)):
        raise RunError(f"{path}: column 'visible_violation' must hold true/false, not {vv.dtype}")
    if not clips["clip_id"].is_unique:
        raise RunError(f"{path}: clip_id {clips['clip_id'][clips['clip_id'].duplicated()].iloc[0]!r} appears twice")
    bad = sorted(set(clips["role"]) - set(ROLES))
    if bad:
        raise RunError(f"{path}: unknown role(s) {bad[:3]}; expected possible or impossible")
    for set_id, g in clips.groupby("set_id", sort=False):
        roles = set(g["role"])
        if roles != set(ROLES):
            raise RunError(f"{path}: matched set {set_id!r} lacks {'possible' if 'possible' not in roles else 'impossible'} clips")
        for col in SET_COLUMNS:  # what a set is grouped by must not split it
            if col in g.columns and g[col].nunique(dropna=False) != 1:
                raise RunError(f"{path}: matched set {set_id!r} has clips with different '{col}' "
                               f"({list(g[col].unique())[:3]})")
