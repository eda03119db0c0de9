"""Locate where recordings part from the nominal simulation.

Why: a single RMSE says the model is wrong, not where. Each short re-initialised window gives a
z-score per body and variable: the residual divided by what a correct model would leave (noise
plus integrated velocity error, see ``Shooter.sigma_pred``). A binary-segmentation change-point
search on each body's sequence of window log-z values splits an episode into stretches of
constant misfit, and stretches whose median z exceeds a threshold calibrated on simulated clean
data are reported with their context (``locate``). When none does but the data depart as a whole
(``voe.gap.departure``), each window is held against its own window-local clean replicates
instead (``locate_local``; why: ``voe.gap.stages.locate_parts``).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import asdict, dataclass

import numpy as np

from voe.gap.context import frame_labels, summarize
from voe.gap.shooting import Shooter, Window

VARS = ("x", "y", "angle")
CLEAN, LOCAL = "clean", "local"  # ``Located.bar``: which bar located a stretch (``locate``, ``locate_local``)


@dataclass(frozen=True)
class Located:
    """A stretch of one episode where one body's recording departs from the model."""

    episode: int
    body: str
    t_start: float
    t_end: float
    variables: list[str]
    context: str
    z: float
    region: list[float]
    # which bar located it: "clean" (the stretch's median window z above ``bar_z``, the clean
    # replicate's 95th-percentile window z: ``locate``) or "local" (each of its windows above every
    # one of that window's own window-local clean replicates and z_min; ``bar_z`` is the largest of
    # those bars over the stretch: ``locate_local``)
    bar: str = CLEAN
    bar_z: float = float("nan")

    def to_dict(self) -> dict:
        return asdict(self)


def by_bar(located: list[dict], bar: str) -> list[dict]:
    """The stretches of ``located`` (``Located.to_dict()``) that ``bar`` (``CLEAN`` or ``LOCAL``) located."""
    return [x for x in located if x["bar"] == bar]


def window_z(shooter: Shooter, windows: list[Window], sigma: np.ndarray,
             residuals: list[np.ndarray] | None = None) -> np.ndarray:
    """(W, B, 3) RMS standardised residual in each window (first sample left out): of the nominal
    model, or of the given ``residuals`` (each (n, B, 3)), so that a fitted model's windows are
    judged by the same figure as the location's threshold."""
    out = []
    res_all = shooter.residuals(windows, None, None) if residuals is None else residuals
    for w, res in zip(windows, res_all, strict=True):
        r = res / shooter.sigma_pred(w, sigma)  # (n, B, 3)
        out.append(np.sqrt(np.mean(r[1:] ** 2, axis=0)))
    return np.array(out)


def change_points(s: np.ndarray, penalty: float) -> list[tuple[int, int]]:
    """Segments [i, j) of constant mean in ``s`` (n,) by binary segmentation.

    A split is kept when it lowers the sum of squared deviations by more than ``penalty``.
    """
    def split(i: int, j: int) -> list[tuple[int, int]]:
        seg = s[i:j]
        if len(seg) < 2:
            return [(i, j)]
        total = float(np.sum((seg - seg.mean()) ** 2))
        best, at = 0.0, -1
        for k in range(1, len(seg)):
            left, right = seg[:k], seg[k:]
            gain = total - float(np.sum((left - left.mean()) ** 2) + np.sum((right - right.mean()) ** 2))
            if gain > best:
                best, at = gain, k
        if at < 0 or best <= penalty:
            return [(i, j)]
        return split(i, i + at) + split(i + at, j)

    return split(0, len(s))


def locate(shooter: Shooter, windows: list[Window], z: np.ndarray, z_thr: float) -> list[Located]:
    """Turn window z-scores (W, B, 3) into located stretches above ``z_thr``."""
    found: list[Located] = []
    for idx, labels, b in _tracks(shooter, windows):
        zb = z[idx, b]  # (n, 3)
        s = np.log(np.maximum(zb.max(axis=1), 1e-3))
        noise = 1.4826 * np.median(np.abs(np.diff(s))) / np.sqrt(2) if len(s) > 2 else 1.0
        penalty = 2.0 * max(noise, 0.1) ** 2 * np.log(max(len(s), 2)) * 2
        for i, j in change_points(s, penalty):
            seg = zb[i:j]  # (m, 3)
            zmed = float(np.median(seg.max(axis=1)))
            if zmed <= z_thr:
                continue
            med = np.median(seg, axis=0)
            vars_ = [v for v, m in zip(VARS, med, strict=True) if m > z_thr] or [VARS[int(np.argmax(med))]]
            found.append(_stretch(shooter, windows, idx[i:j], b, labels, vars_, zmed, CLEAN, z_thr))
    return found


def locate_local(shooter: Shooter, windows: list[Window], z: np.ndarray, bars: np.ndarray) -> list[Located]:
    """Stretches of back-to-back windows where a body's largest z of ``z`` (W, B, 3) exceeds the
    window's own bar ``bars`` (W,): each window held against the clean replicates of that window,
    not one threshold for all (why and when: ``voe.gap.stages.locate_parts``). A stretch's z is
    the median of its windows' z, its variables those whose median exceeds its largest bar."""
    found: list[Located] = []
    for idx, labels, b in _tracks(shooter, windows):
        above = z[idx, b].max(axis=1) > bars[idx]  # (n,)
        k = 0
        while k < len(idx):
            if not above[k]:
                k += 1
                continue
            j = k
            while j < len(idx) and above[j]:
                j += 1
            seg, bar = z[idx[k:j], b], float(np.max(bars[idx[k:j]]))  # (m, 3)
            med = np.median(seg, axis=0)
            vars_ = [v for v, m in zip(VARS, med, strict=True) if m > bar] or [VARS[int(np.argmax(med))]]
            found.append(_stretch(shooter, windows, idx[k:j], b, labels, vars_,
                                  float(np.median(seg.max(axis=1))), LOCAL, bar))
            k = j
    return found


def _tracks(shooter: Shooter, windows: list[Window]) -> Iterator[tuple[list[int], np.ndarray, int]]:
    """Each episode's window indices in ``windows``, its frame labels (T, B) and a body index, for
    every episode and body: the sequences both bars scan."""
    for ep_i in sorted({w.ep for w in windows}):
        idx = [i for i, w in enumerate(windows) if w.ep == ep_i]
        labels = frame_labels(shooter.scene, shooter.episodes[ep_i])  # (T, B)
        for b in range(len(shooter.scene.names)):
            yield idx, labels, b


def _stretch(shooter: Shooter, windows: list[Window], idx: list[int], b: int, labels: np.ndarray,
             variables: list[str], z: float, bar: str, bar_z: float) -> Located:
    """The ``Located`` of body ``b`` over back-to-back windows ``idx`` of one episode, with the
    context and region of its frames (``labels`` (T, B): that episode's frame labels)."""
    w0, w1 = windows[idx[0]], windows[idx[-1]]
    ep = shooter.episodes[w0.ep]
    ctx, region = summarize(labels[w0.k0:w1.k1 + 1, b], ep.pose[w0.k0:w1.k1 + 1, b])
    return Located(ep.id, shooter.scene.names[b], float(ep.t[w0.k0]), float(ep.t[w1.k1]), variables, ctx,
                   round(z, 2), [round(r, 4) for r in region], bar, round(bar_z, 2))
