"""Read and check recordings (CSV or parquet with ``episode, t, body, x, y, angle``).

Why: the finder estimates velocities from poses, so a NaN, a repeated time stamp or a missing body
would silently corrupt everything downstream. Each problem raises one ``DataError`` that names
the problem and the file.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from voe.errors import DataError
from voe.gap.outliers import Outlier, find_outliers, non_finite_or_huge
from voe.sim.scenefile import SceneSpec

COLUMNS = ("episode", "t", "body", "x", "y", "angle")
MIN_SAMPLES = 20


@dataclass(frozen=True)
class Episode:
    """One recorded episode. ``pose`` is (T, B, 3) in scene body order; ``t`` is (T,).

    ``outliers`` lists the isolated spikes kept when loading with ``outliers="flag"``.
    """

    id: int
    t: np.ndarray
    pose: np.ndarray
    outliers: tuple[Outlier, ...] = field(default=())


def read_table(path: str | Path) -> pd.DataFrame:
    """Load the raw table from CSV or parquet."""
    path = Path(path)
    if not path.exists():
        raise DataError(f"recordings file not found: {path}")
    try:
        if path.suffix.lower() in (".parquet", ".pq"):
            return pd.read_parquet(path)
        return pd.read_csv(path)
    except Exception as exc:  # pandas raises many types for malformed files
        raise DataError(f"cannot read recordings {path}: {exc}") from exc


def load_recordings(path: str | Path, scene: SceneSpec, table: pd.DataFrame | None = None,
                    outliers: str = "refuse") -> list[Episode]:
    """Validate recordings against ``scene`` and split them into episodes.

    Args:
        path: the file (also used in error messages).
        scene: bodies must match the scene's names.
        table: an already loaded table (for in-memory use); read from ``path`` otherwise.
        outliers: ``"refuse"`` an isolated spike (see ``voe.gap.outliers``), or ``"flag"`` it:
            keep the sample and list it in its episode's ``outliers``.

    Raises:
        DataError: unknown body, missing column, NaN, infinite or impossibly large values, an
            isolated spike (unless flagged), non-increasing time, an episode shorter than
            ``MIN_SAMPLES`` samples, or a scene body without recordings.
    """
    if outliers not in ("refuse", "flag"):
        raise DataError(f"outliers must be 'refuse' or 'flag', got {outliers!r}")
    df = read_table(path) if table is None else table
    missing = [c for c in COLUMNS if c not in df.columns]
    if missing:
        raise DataError(f"recordings {path} are missing column(s) {', '.join(missing)} (need {', '.join(COLUMNS)})")
    for col in ("episode", "t", "x", "y", "angle"):
        vals = pd.to_numeric(df[col], errors="coerce")
        if vals.isna().any():
            row = int(np.flatnonzero(vals.isna().to_numpy())[0])
            raise DataError(f"recordings {path} have NaN or non-numeric '{col}' at data row {row + 1}")
    bad = non_finite_or_huge(df, ("episode", "t", "x", "y", "angle"))
    if bad:
        raise DataError(f"recordings {path} have {bad}")
    if df["body"].isna().any():
        raise DataError(f"recordings {path} have an empty 'body' at data row {int(np.flatnonzero(df['body'].isna())[0]) + 1}")
    names = scene.names
    unknown = sorted(set(df["body"].astype(str)) - set(names))
    if unknown:
        raise DataError(f"recordings {path} name unknown body {unknown[0]!r}; scene bodies are {names}")
    absent = [n for n in names if n not in set(df["body"].astype(str))]
    if absent:
        raise DataError(f"scene body {absent[0]!r} has no recordings in {path}")
    spikes = find_outliers(df, names)
    if spikes and outliers == "refuse":
        more = f" (and {len(spikes) - 1} more)" if len(spikes) > 1 else ""
        raise DataError(f"recordings {path}: {spikes[0].describe()}{more}; fix or drop the row, "
                        f"or load with outliers='flag'")
    episodes = []
    for ep, g in df.groupby("episode", sort=True):
        e = _episode(int(ep), g, names, path)
        flagged = tuple(o for o in spikes if o.episode == e.id)
        episodes.append(Episode(e.id, e.t, e.pose, flagged) if flagged else e)
    return episodes


def _episode(ep: int, g: pd.DataFrame, names: list[str], path: str | Path) -> Episode:
    t_ref = None
    poses = []
    for name in names:
        gb = g[g["body"].astype(str) == name]
        if gb.empty:
            raise DataError(f"scene body {name!r} has no recordings in episode {ep} of {path}")
        t = gb["t"].to_numpy(dtype=float)
        bad = np.flatnonzero(np.diff(t) <= 0)
        if bad.size:
            raise DataError(f"recordings {path}: time does not increase for body {name!r} in episode {ep} at t = {t[bad[0] + 1]:g}")
        if t_ref is None:
            t_ref = t
        elif t.shape != t_ref.shape or not np.allclose(t, t_ref, atol=1e-9):
            raise DataError(f"recordings {path}: body {name!r} in episode {ep} has different time stamps than {names[0]!r}")
        poses.append(gb[["x", "y", "angle"]].to_numpy(dtype=float))
    assert t_ref is not None
    if len(t_ref) < MIN_SAMPLES:
        raise DataError(f"recordings {path}: episode {ep} is too short ({len(t_ref)} samples, need {MIN_SAMPLES})")
    return Episode(ep, t_ref, np.stack(poses, axis=1))  # (T, B, 3)
