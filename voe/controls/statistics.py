"""Knowledge-free scorers: statistics of the stored bytes that know no physics at all.

Why: if a scorer that knows nothing about a concept separates its impossible clips from the
possible ones, the probe measures that statistic, not the concept. Each scorer here gives a
per-frame "surprise" whose clip sum is an order-free statistic of the clip:

* ``density``: ``-log p(frame)`` under an independent per-pixel Bernoulli fitted on the probe
  set's own frames (a function of single frames: ties exactly on F-balanced sets);
* ``motion-energy``: the per-step change ``sum |x_t - x_{t-1}|`` (a function of single steps:
  ties exactly on M-balanced sets; its sum over a clip is the clip's total motion);
* ``height``: the mean height ``y`` of the visible objects (state space);
* ``speed``: the summed speed ``|v|`` of the visible objects (state space).

A scorer's direction is arbitrary (more motion = more surprise), which is why its declaration
is ``chance``: off chance *either way* means the probe set gives the answer away.

Each scorer is a ``Statistic``: optional ``fit`` on the whole probe set (unsupervised, never
looking at roles) and ``traces(arrays) -> (B, T)``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from voe.io.probeset import ProbeSet

#: Pixels above this are "on" for the density (screens are drawn at 64, objects at >= 153).
DENSITY_THRESHOLD = 40


def concept_chunks(ps: ProbeSet) -> Iterator[tuple[str, np.ndarray, dict[str, np.ndarray]]]:
    """Per concept: ``(concept, index rows (n,), arrays of its clips)``, to bound memory."""
    concepts = ps.index["concept"].to_numpy()
    ids = ps.index["clip_id"].to_numpy()
    for concept in sorted(set(concepts)):
        rows = np.flatnonzero(concepts == concept)
        yield str(concept), rows, ps.get(ids[rows].tolist())


def _feature(arrays: dict[str, np.ndarray], names: tuple[str, ...], name: str) -> np.ndarray:
    s = arrays["states"][..., names.index(name)].astype(np.float64)  # (B, T, K)
    return np.where(arrays["present"], s, np.nan)


class Statistic:
    """Base: a named per-frame statistic of a clip (see the module docstring)."""

    name: ClassVar[str]
    invariant_to: ClassVar[str]  # the balance ('F', 'M' or 'S') on which it ties by construction
    why: ClassVar[str]

    def fit(self, ps: ProbeSet) -> Statistic:
        return self

    def traces(self, arrays: dict[str, np.ndarray], names: tuple[str, ...]) -> np.ndarray:
        raise NotImplementedError


class Density(Statistic):
    name, invariant_to = "density", "F"
    why = "a per-frame pixel density: sees one frame at a time, knows nothing of time or physics"

    def __init__(self) -> None:
        self.logp_on: np.ndarray | None = None
        self.logp_off: np.ndarray | None = None

    def fit(self, ps: ProbeSet) -> Density:
        on, n = 0.0, 0
        for _, _, arrays in concept_chunks(ps):
            bits = arrays["frames"] > DENSITY_THRESHOLD  # (B, T, H, W)
            on, n = on + bits.sum(axis=(0, 1)), n + bits.shape[0] * bits.shape[1]
        p = (on + 1.0) / (n + 2.0)  # (H, W) add-one smoothing
        self.logp_on, self.logp_off = np.log(p), np.log1p(-p)
        return self

    def traces(self, arrays, names):
        bits = arrays["frames"] > DENSITY_THRESHOLD  # (B, T, H, W)
        return -np.where(bits, self.logp_on, self.logp_off).sum(axis=(2, 3))  # (B, T)


class MotionEnergy(Statistic):
    name, invariant_to = "motion-energy", "M"
    why = "the order-free sum of per-step change |x_t - x_t-1|: amount of motion, no physics"

    def traces(self, arrays, names):
        x = arrays["frames"].astype(np.int32)  # (B, T, H, W)
        out = np.zeros(x.shape[:2])
        out[:, 1:] = np.abs(x[:, 1:] - x[:, :-1]).sum(axis=(2, 3))  # (B, T-1) exact integers
        return out


class Height(Statistic):
    name, invariant_to = "height", "S"
    why = "mean height of the visible objects: where things are, not how they move"

    def traces(self, arrays, names):
        y = _feature(arrays, names, "y")  # (B, T, K)
        n = (~np.isnan(y)).sum(-1)
        return np.where(n > 0, np.nansum(y, -1) / np.maximum(n, 1), 0.0)  # (B, T)


class Speed(Statistic):
    name, invariant_to = "speed", "S"
    why = "summed speed of the visible objects: how much moves, not whether it may"

    def traces(self, arrays, names):
        v = np.hypot(_feature(arrays, names, "vx"), _feature(arrays, names, "vy"))  # (B, T, K)
        return np.nansum(v, -1)  # (B, T)


#: name -> Statistic class; the knowledge-free family of the specificity matrix reads this.
STATISTICS: dict[str, type[Statistic]] = {c.name: c for c in (Density, MotionEnergy, Height, Speed)}


@dataclass(frozen=True)
class StatTraces:
    """Per-frame traces ``(N, T)`` of one statistic, rows in probe-set index order."""

    name: str
    traces: np.ndarray
    info: dict[str, Any]


def statistic_traces(ps: ProbeSet, stat: Statistic) -> StatTraces:
    """Fit ``stat`` on the probe set (unsupervised) and compute its traces for every clip."""
    stat.fit(ps)
    out: np.ndarray | None = None
    for _, rows, arrays in concept_chunks(ps):
        tr = stat.traces(arrays, ps.feature_names)  # (n, T)
        if out is None:
            out = np.full((len(ps), tr.shape[1]), np.nan)
        out[rows] = tr
    assert out is not None
    return StatTraces(stat.name, out, {"invariant_to": stat.invariant_to})
