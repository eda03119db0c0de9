"""A smoothness statistic of object tracks: a physics-poor reference in the style of GeoPhys.

Why: a training-free statistic of how smoothly per-frame features move ("GeoPhys", 2026) scores
93% on IntPhys 2. Here it reads object tracks (the stored states): per visible object and frame,
the second difference of its position (a change of velocity) plus the turning angle between
successive steps. An object that reappears after a gap is compared with the velocity it had
when last seen, spread over the gap, so a teleport behind a screen is a jolt too.

It knows smooth motion, i.e. continuity and inertia, and nothing else: no gravity (free fall is
a constant second difference like any other), no collisions (a bounce is a jolt whether or not
something was hit), no solidity, no energy, no object identity beyond "the same slot". The
specificity matrix holds it to that.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from voe.controls.statistics import Statistic

#: A second difference of this many scene units per frame counts as much as a turn of 1 radian.
ACC_SCALE = 0.05
#: Steps shorter than this (scene units per frame) have no direction to turn from.
MIN_STEP = 1e-3


class Smoothness(Statistic):
    """Per-frame jolt of the visible tracks (see the module docstring)."""

    name: ClassVar[str] = "smoothness"
    invariant_to: ClassVar[str] = ""
    why: ClassVar[str] = ("smoothness of object tracks (second differences, turning angles): knows "
                          "continuity and inertia only")

    def traces(self, arrays: dict[str, np.ndarray], names: tuple[str, ...]) -> np.ndarray:
        xy = arrays["states"][..., [names.index("x"), names.index("y")]].astype(np.float64)  # (B, T, K, 2)
        seen = arrays["present"] & ~np.isnan(xy).any(-1)  # (B, T, K)
        B, T, K, _ = xy.shape
        out = np.zeros((B, T))
        last_p = np.full((B, K, 2), np.nan)  # last seen position
        last_t = np.full((B, K), -1)
        last_v = np.full((B, K, 2), np.nan)  # last velocity (per frame)
        for t in range(T):
            s = seen[:, t]  # (B, K)
            gap = np.maximum(t - last_t, 1)[..., None]  # (B, K, 1)
            v = (xy[:, t] - last_p) / gap  # (B, K, 2) NaN where never seen before
            acc = np.linalg.norm(v - last_v, axis=-1)  # (B, K)
            sp, sp0 = np.linalg.norm(v, axis=-1), np.linalg.norm(last_v, axis=-1)
            cos = (v * last_v).sum(-1) / np.maximum(sp * sp0, 1e-12)
            turn = np.where((sp > MIN_STEP) & (sp0 > MIN_STEP), np.arccos(np.clip(cos, -1, 1)), 0.0)
            jolt = np.where(s & ~np.isnan(acc), acc / ACC_SCALE + turn, 0.0)  # (B, K)
            out[:, t] = np.nan_to_num(jolt).sum(-1)
            last_v = np.where(s[..., None] & ~np.isnan(v), v, last_v)
            last_p = np.where(s[..., None], xy[:, t], last_p)
            last_t = np.where(s, t, last_t)
        return out

