"""Absurd values in recordings: non-finite, impossibly large, or isolated spikes.

Why: one x of 1e300 once passed validation and gave a normal gap verdict with "largest z = inf".
The finder estimates velocities from poses, so a single glitched sample poisons every window it
touches. Non-finite and impossibly large values are always refused. An isolated spike (one sample
far from both neighbours, in the same direction, by much more than the series' own
sample-to-sample scale *and* by a large share of the body's range of motion) is refused by
default or, on request, flagged per row so that the caller reports it. Impacts are not spikes: a
bounce's lowest sample sits about ``v dt`` below its neighbours, a small share of the range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

POSE = ("x", "y", "angle")
MAX_ABS = 1e6     # metres or radians: no recorded pose is this large
Z_MAX = 100.0     # spike height over the robust scale of second differences
RANGE_FRAC = 0.25  # spike height over the body's 5-95 % range of that variable in the episode


@dataclass(frozen=True)
class Outlier:
    """One suspicious sample. ``row`` is the 1-based data row of the file (header excluded)."""

    row: int
    episode: int
    body: str
    column: str
    value: float
    z: float
    range_share: float

    def describe(self) -> str:
        return (f"data row {self.row} (episode {self.episode}, body {self.body!r}, {self.column} = {self.value:.6g}) "
                f"is an isolated spike: {self.z:.0f}x the sample-to-sample scale, "
                f"{100 * self.range_share:.0f} % of the body's range")


def non_finite_or_huge(df: pd.DataFrame, cols: tuple[str, ...]) -> str | None:
    """A one-line reason naming the first infinite or impossibly large value, or None.

    ``df`` must already hold numbers in ``cols`` (NaN is reported by the caller).
    """
    for col in cols:
        vals = pd.to_numeric(df[col], errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(vals) & ~np.isnan(vals)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            return f"non-finite '{col}' ({vals[k]}) at data row {k + 1}"
        if col in POSE:
            huge = np.abs(vals) > MAX_ABS
            if huge.any():
                k = int(np.flatnonzero(huge)[0])
                return (f"impossibly large '{col}' ({vals[k]:.3g}, beyond {MAX_ABS:.0e} m or rad) "
                        f"at data row {k + 1}")
    return None


def _spikes(v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per sample of a (T,) series: spike height, robust z and share of the range."""
    n = len(v)
    size = np.zeros(n)
    if n < 4:
        return size, size.copy(), size.copy()
    left, right = v[1:-1] - v[:-2], v[1:-1] - v[2:]
    same = np.sign(left) == np.sign(right)
    size[1:-1] = np.where(same, np.minimum(np.abs(left), np.abs(right)), 0.0)
    size[0] = abs(v[0] - (2 * v[1] - v[2]))     # ends: distance from the linear extrapolation
    size[-1] = abs(v[-1] - (2 * v[-2] - v[-3]))
    d2 = np.abs(v[2:] - 2 * v[1:-1] + v[:-2])
    scale = max(1.4826 * float(np.median(d2)), 1e-12 * (1.0 + float(np.median(np.abs(v)))))
    p5, p95 = np.percentile(v, [5, 95])
    spread = max(float(p95 - p5), scale)
    return size, size / scale, size / spread


def find_outliers(df: pd.DataFrame, names: list[str]) -> list[Outlier]:
    """Isolated spikes in ``x, y, angle`` per episode and body (rows in file order)."""
    out: list[Outlier] = []
    df = df.reset_index(drop=True)
    for (ep, body), g in df.groupby(["episode", df["body"].astype(str)], sort=True):
        if body not in names:
            continue
        g = g.sort_values("t", kind="stable")
        for col in POSE:
            v = pd.to_numeric(g[col]).to_numpy(dtype=float)
            _, z, share = _spikes(v)
            for k in np.flatnonzero((z > Z_MAX) & (share > RANGE_FRAC)):
                out.append(Outlier(int(g.index[k]) + 1, int(ep), str(body), col, float(v[k]),
                                   float(z[k]), float(share[k])))
    return sorted(out, key=lambda o: (o.row, o.column))
