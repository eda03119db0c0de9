"""Per-slot input features for the learned state models (numpy; no torch).

Why: the object-centric model must know what the probes test without being told about them:
where each object is and how it moves (carried forward while hidden: per-slot memory), which
static segment it is about to touch (floors, shelves, ramps, walls from ``batch.geometry``) and
whether it should be visible next frame (inside the window and not fully behind a screen). These
are plain geometry on the observation and the stored scene geometry, computed once per batch.

Layout of ``slot_features`` (``D = 28`` per slot, predicting frame t+1 from frames <= t)::

    0-10  memory: x/10, y/10, sin, cos(angle), vx/5, vy/5, omega/5, is_circle, width, height, intensity
    11-13 present now, known (seen at or before t), min(age, 20)/10 (frames since last seen)
    14-23 two nearest static segments: (dx, dy)/5 to the nearest point, clearance, unit tangent
    24-27 hidden now, outside now, hidden next, outside next (constant-velocity guess for t+1)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.io.batch import Batch
from voe.models import statelik as sl

D = 28
LAYOUT_VERSION = 1


def _half_extents(mem: np.ndarray, ix: dict[str, int]) -> tuple[np.ndarray, np.ndarray]:
    w, h, a = mem[..., ix["width"]] / 2, mem[..., ix["height"]] / 2, mem[..., ix["angle"]]
    box = mem[..., ix["is_circle"]] < 0.5
    c, s = np.abs(np.cos(a)), np.abs(np.sin(a))
    return np.where(box, c * w + s * h, w), np.where(box, s * w + c * h, h)


def _hidden_outside(x: np.ndarray, y: np.ndarray, hx: np.ndarray, hy: np.ndarray,
                    geo: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    ex, ey = geo.get("extent", (10.0, 10.0))
    outside = (x + hx <= 0) | (x - hx >= ex) | (y + hy <= 0) | (y - hy >= ey)
    hidden = np.zeros_like(outside)
    for o in geo.get("occluders", []):
        hidden |= ((o["x0"] <= x - hx) & (x + hx <= o["x1"]) & (o["y0"] <= y - hy) & (y + hy <= o["y1"]))
    return hidden, outside


def _statics(x: np.ndarray, y: np.ndarray, half: np.ndarray, geo: dict[str, Any]) -> np.ndarray:
    """``(..., 10)``: the two nearest segments' offset, clearance and tangent."""
    feats = []
    for s in geo.get("statics", []):
        ax, ay = s["a"]
        bx, by = s["b"]
        vx, vy = bx - ax, by - ay
        L2 = max(vx * vx + vy * vy, 1e-12)
        h = np.clip(((x - ax) * vx + (y - ay) * vy) / L2, 0, 1)
        dx, dy = ax + h * vx - x, ay + h * vy - y
        clear = np.hypot(dx, dy) - s["radius"] - half
        L = np.sqrt(L2)
        tx, ty = (vx / L, vy / L) if vx >= 0 else (-vx / L, -vy / L)
        feats.append(np.stack([dx / 5, dy / 5, clear, np.full_like(x, tx), np.full_like(x, ty)], -1))
    far = np.stack([np.full_like(x, 2.0), np.full_like(x, 2.0), np.full_like(x, 10.0),
                    np.zeros_like(x), np.zeros_like(x)], -1)
    while len(feats) < 2:
        feats.append(far)
    allf = np.stack(feats, -2)  # (..., S, 5)
    order = np.argsort(allf[..., 2], axis=-1)[..., :2]  # two smallest clearances
    best = np.take_along_axis(allf, order[..., None], axis=-2)  # (..., 2, 5)
    best[..., 2] = np.clip(best[..., 2], -1, 3)
    return best.reshape(*x.shape, 10)


def slot_features(batch: Batch) -> dict[str, np.ndarray]:
    """Inputs and targets of the learned state models for a batch.

    Returns:
        ``x`` (B, T, K, D) float32 inputs at t; ``mem`` (B, T, K, 9) memory CONT at t;
        ``base`` (B, T, K, 9) constant-velocity guess for t+1; ``known``, ``present`` (B, T, K);
        ``obs`` (B, T, K, 9) observed CONT (0 where absent); ``circle`` (B, T, K) observed shape.
    """
    names = batch.feature_names
    idx = sl.cont_index(names)
    ix = {n: i for i, n in enumerate(names)}
    states = batch.states.astype(np.float64)
    mem, known, age = sl.carry(states, batch.present, batch.dt,
                               lambda s, dt: sl.constant_velocity_step(s, dt, names))
    mem = np.nan_to_num(mem)  # (B, T, K, F); zeros for never-seen slots
    B, T, K, _ = mem.shape
    nxt = mem.reshape(-1, mem.shape[-1])
    nxt = sl.constant_velocity_step(nxt, batch.dt, names).reshape(mem.shape)
    hx, hy = _half_extents(mem, ix)
    x = np.zeros((B, T, K, D), dtype=np.float64)
    m = mem
    x[..., 0], x[..., 1] = m[..., ix["x"]] / 10, m[..., ix["y"]] / 10
    x[..., 2], x[..., 3] = np.sin(m[..., ix["angle"]]), np.cos(m[..., ix["angle"]])
    x[..., 4], x[..., 5], x[..., 6] = m[..., ix["vx"]] / 5, m[..., ix["vy"]] / 5, m[..., ix["omega"]] / 5
    for j, f in enumerate(("is_circle", "width", "height", "intensity")):
        x[..., 7 + j] = m[..., ix[f]]
    x[..., 11], x[..., 12], x[..., 13] = batch.present, known, np.minimum(age, 20) / 10
    for b in range(B):
        geo = batch.geometry[b] if batch.geometry else {}
        x[b, ..., 14:24] = _statics(m[b, ..., ix["x"]], m[b, ..., ix["y"]], np.maximum(hx[b], hy[b]), geo)
        hid, out = _hidden_outside(m[b, ..., ix["x"]], m[b, ..., ix["y"]], hx[b], hy[b], geo)
        x[b, ..., 24], x[b, ..., 25] = hid, out
        hid, out = _hidden_outside(nxt[b, ..., ix["x"]], nxt[b, ..., ix["y"]], hx[b], hy[b], geo)
        x[b, ..., 26], x[b, ..., 27] = hid, out
    x[~known] = 0.0
    obs = np.nan_to_num(states[..., idx])
    return {"x": x.astype(np.float32), "mem": mem[..., idx].astype(np.float32),
            "base": nxt[..., idx].astype(np.float32), "known": known, "present": batch.present.copy(),
            "obs": obs.astype(np.float32),
            "circle": np.nan_to_num(states[..., ix["is_circle"]]) > 0.5}


def layout(batch: Batch) -> dict[str, Any]:
    """What a checkpoint of a state model records about its inputs."""
    return {"feature_names": list(batch.feature_names), "n_slots": int(batch.states.shape[2]),
            "input_dim": D, "layout_version": LAYOUT_VERSION}
