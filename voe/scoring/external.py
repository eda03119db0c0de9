"""Score surprises computed outside voe: a table ``clip_key, frame, surprise`` (csv or parquet).

Why: video world models (V-JEPA, Cosmos, diffusion models) are run by their own code on the
exported clips (``voe probes export``), which name clips by opaque keys only. Their per-frame (or
per-clip) surprise comes back as a table keyed the same way; joined to the probe set's index here,
it becomes an ordinary run directory, so the statistics and the report are exactly those of an
in-process model.

Table rules (each broken rule is one line naming the file):

* columns ``clip_key`` (the 16-hex key of ``voe.io.clipkey.clip_key``) and ``surprise`` (numbers),
  and optionally ``frame`` (integers, ``0 <= frame < T``); other columns are ignored;
* every clip of the probe set appears, no key is unknown, no ``(clip_key, frame)`` (or, without
  ``frame``, no ``clip_key``) appears twice, and every surprise is finite;
* frames left out are not scored (NaN); a set's clips are compared on the frames scored in all
  of them. Without ``frame``, the one value per clip is stored as the surprise of its last frame,
  the first at which a model has seen the whole clip.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe.errors import VoeError
from voe.io.clipkey import clip_key
from voe.io.paths import portable_ref
from voe.io.probeset import ProbeSet, load_probe_set
from voe.io.provenance import sha256_file
from voe.scoring.store import SURPRISE_KINDS, write_run

REQUIRED = ("clip_key", "surprise")


def _bad(path: Path, why: str) -> VoeError:
    return VoeError(f"surprise table {path}: {why}")


def read_table(path: Path) -> pd.DataFrame:
    """Read a csv or parquet surprise table, with ``clip_key`` as text whatever it looks like."""
    path = Path(path)
    if not path.is_file():
        raise _bad(path, "does not exist or is not a file")
    suffix = path.suffix.lower()
    try:
        if suffix == ".csv":
            df = pd.read_csv(path, dtype={"clip_key": str})
        elif suffix in (".parquet", ".pq"):
            df = pd.read_parquet(path)
        else:
            raise _bad(path, f"unknown suffix {suffix!r}; give a .csv or .parquet file")
    except VoeError:
        raise
    except Exception as exc:  # pandas and pyarrow raise many types for damaged files
        raise _bad(path, f"cannot be read ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})") from exc
    return df


def _frames(path: Path, col: pd.Series, T: int) -> np.ndarray:
    """The ``frame`` column as integers in ``0..T-1`` (checked before any cast can overflow)."""
    vals = col.astype(float).to_numpy()
    ok = np.isfinite(vals) & (vals == np.round(vals))
    if not ok.all():
        row = int(np.flatnonzero(~ok)[0])
        raise _bad(path, f"column 'frame' must hold whole numbers; row {row} has {col.iloc[row]!r}")
    out = (vals < 0) | (vals >= T)
    if out.any():
        row = int(np.flatnonzero(out)[0])
        raise _bad(path, f"frame {col.iloc[row]!r} in row {row} is outside 0..{T - 1}")
    return vals.astype(np.int64)


def table_to_nll(path: Path, df: pd.DataFrame, keys: list[str], T: int) -> np.ndarray:
    """Check ``df`` against the probe set's clip ``keys`` and return surprise ``(N, T)``."""
    missing = [c for c in REQUIRED if c not in df.columns]
    if missing:
        raise _bad(path, f"lacks column(s) {missing}; expected clip_key, [frame,] surprise")
    if df.empty:
        raise _bad(path, "has no rows")
    try:
        key_list = df["clip_key"].tolist()
    except Exception as exc:  # noqa: BLE001 - a parquet string column holding bytes that are not UTF-8
        raise _bad(path, f"column 'clip_key' is not valid UTF-8 text ({exc})") from exc
    if not all(isinstance(k, str) for k in key_list):
        row = int(np.flatnonzero([not isinstance(k, str) for k in key_list])[0])
        raise _bad(path, f"column 'clip_key' must hold text keys; row {row} has {df['clip_key'].iloc[row]!r}")
    for col in ("surprise", "frame"):
        if col in df.columns and (not pd.api.types.is_numeric_dtype(df[col]) or pd.api.types.is_bool_dtype(df[col])):
            raise _bad(path, f"column '{col}' must hold numbers, not {df[col].dtype} "
                             f"(first value {df[col].iloc[0]!r})")
    surprise = df["surprise"].astype(float).to_numpy()
    if not np.isfinite(surprise).all():
        row = int(np.flatnonzero(~np.isfinite(surprise))[0])
        raise _bad(path, f"surprise must be a finite number; row {row} has {df['surprise'].iloc[row]!r}")
    pos = {k: i for i, k in enumerate(keys)}
    present = set(df["clip_key"])
    unknown = sorted(present - set(pos))
    if unknown:
        raise _bad(path, f"{len(unknown)} clip_key(s) are not clips of this probe set, e.g. {unknown[0]!r}; "
                         "was it made from another export?")
    absent = [k for k in keys if k not in present]
    if absent:
        raise _bad(path, f"{len(absent)} of {len(keys)} clips have no surprise, e.g. {absent[0]!r}")
    if "frame" in df.columns:
        frame = _frames(path, df["frame"], T)
    else:
        frame = np.full(len(df), T - 1)
    rows = df["clip_key"].map(pos).to_numpy()
    dup = pd.Series(rows * T + frame).duplicated().to_numpy()
    if dup.any():
        row = int(np.flatnonzero(dup)[0])
        what = f"frame {frame[row]} of clip_key" if "frame" in df.columns else "clip_key"
        raise _bad(path, f"{what} {df['clip_key'].iloc[row]!r} appears more than once (row {row})")
    nll = np.full((len(keys), T), np.nan)  # (N, T)
    nll[rows, frame] = surprise
    return nll


def score_surprises(probes: ProbeSet | str | Path, surprises: Path, out: Path, *, kind: str = "nll",
                    name: str | None = None, overwrite: bool = False) -> dict[str, Any]:
    """Write a run directory from an outside surprise table (see the module docstring)."""
    if kind not in SURPRISE_KINDS:
        raise VoeError(f"--surprise-kind must be one of {SURPRISE_KINDS}, not {kind!r}")
    out = Path(out)
    if out.exists() and (not out.is_dir() or any(out.iterdir())) and not overwrite:
        raise VoeError(f"output {out} already exists and is not an empty directory (pass --overwrite)")
    ps = probes if isinstance(probes, ProbeSet) else load_probe_set(probes)
    surprises = Path(surprises)
    index = ps.index.sort_values("row").reset_index(drop=True)
    keys = [clip_key(ps.manifest_sha256, str(c)) for c in index["clip_id"]]
    T = int(ps.manifest.get("n_frames") or ps.get([str(index["clip_id"][0])])["frames"].shape[1])
    table = read_table(surprises)
    nll = table_to_nll(surprises, table, keys, T)
    meta = {
        "model": {"ref": None, "class": None, "args": {}, "name": name or surprises.stem, "observation": "",
                  "checkpoint": None, "checkpoint_sha256": None,
                  "surprises": {"file": surprises.name, "sha256": sha256_file(surprises),
                                "per_frame": "frame" in table.columns}},
        "surprise_kind": kind,
        "probes": {"path": portable_ref(ps.path, out), "manifest_sha256": ps.manifest_sha256,
                   "concepts": list(ps.manifest.get("concepts", []))},
        "check": "n/a (outside voe)",
        "launcher": {"name": "external", "world_size": 1}, "clips_from_cache": 0, "wall_time_s": 0.0,
    }
    return write_run(out, index, nll, meta, overwrite=overwrite)
