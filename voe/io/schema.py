"""Types and ranges of a probe set's manifest and index, checked when the set is opened.

Why: every later step (validation, batching, scoring, reports) indexes these fields without
looking; a manifest whose ``frame_size`` is a string, or an index whose ``row`` holds floats,
used to end in a ``TypeError`` or ``KeyError`` traceback far from the file. Fuzzing found each
check below. All problems raise ``ProbeSetError`` naming the file and the field.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe.errors import ProbeSetError


def _int(v: Any, lo: int = 0) -> bool:
    return isinstance(v, int) and not isinstance(v, bool) and lo <= v < 2**31


def check_manifest(m: dict[str, Any], mpath: Path) -> None:
    """Fields every reader relies on have the right type and range."""
    def bad(field: str, want: str) -> ProbeSetError:
        return ProbeSetError(f"{mpath}: '{field}' must be {want}, got {m.get(field)!r:.80}")

    for field in ("n_clips", "n_frames", "n_slots"):
        if field in m and not _int(m[field], 1 if field == "n_frames" else 0):
            raise bad(field, "a non-negative integer" if field != "n_frames" else "a positive integer")
    size = m.get("frame_size")
    if size is not None and not (isinstance(size, list) and len(size) == 2 and all(_int(s, 1) for s in size)):
        raise bad("frame_size", "[height, width] in pixels")
    names = m.get("feature_names")
    if not (isinstance(names, list) and names and all(isinstance(n, str) for n in names)):
        raise bad("feature_names", "a non-empty list of names")
    dt = m.get("dt")
    if not (isinstance(dt, int | float) and not isinstance(dt, bool) and math.isfinite(dt) and dt > 0):
        raise bad("dt", "a positive number of seconds")
    for field in ("concepts",):
        if field in m and not (isinstance(m[field], list) and all(isinstance(c, str) for c in m[field])):
            raise bad(field, "a list of names")


_TEXT = ("clip_id", "concept", "set_id", "variant", "role")


def check_index(index: pd.DataFrame, ipath: Path, n_rows: int) -> None:
    """Text columns hold text, clip ids are unique, ``row`` numbers the stored clips exactly."""
    for col in _TEXT:
        values = index[col].to_numpy()
        bad = [i for i, v in enumerate(values) if not isinstance(v, str)]
        if bad:
            raise ProbeSetError(f"{ipath}: column '{col}' must hold text; row {bad[0]} has {values[bad[0]]!r:.80}")
    if not index["clip_id"].is_unique:
        dup = index["clip_id"][index["clip_id"].duplicated()].iloc[0]
        raise ProbeSetError(f"{ipath}: clip_id {dup!r} appears more than once")
    for col in ("row", "onset_frame", "n_distractors"):
        if not pd.api.types.is_integer_dtype(index[col]) or pd.api.types.is_bool_dtype(index[col]):
            raise ProbeSetError(f"{ipath}: column '{col}' must hold integers, not {index[col].dtype}")
    rows = index["row"].to_numpy()
    if len(rows) != n_rows or not np.array_equal(np.sort(rows), np.arange(n_rows)):
        raise ProbeSetError(f"{ipath}: column 'row' must number the {n_rows} stored clips 0..{n_rows - 1} once each")
    if not all(isinstance(g, str) for g in index["geometry"]):
        raise ProbeSetError(f"{ipath}: column 'geometry' must hold JSON text")
