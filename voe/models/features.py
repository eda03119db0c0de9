"""Per-slot input features of the flat ``mlp`` state model (numpy; no torch).

Why: a model without object structure and without a memory of its own needs the memory handed
to it: where each object is and how it moves (carried forward while hidden at constant velocity:
per-slot memory; a physics prior, so random ``mlp`` networks can read hidden splices), which
static segment it is about to touch (floors, shelves, ramps, walls from ``batch.geometry``) and
whether it should be visible next frame (inside the window and not fully behind a screen). These
are plain geometry on the observation and the stored scene geometry, computed once per batch.

Layout of ``slot_features`` (``D = 32`` per slot, predicting frame t+1 from frames <= t)::

    0-10  memory: x/10, y/10, sin, cos(angle), vx/5, vy/5, omega/5, is_circle, width, height, intensity
    11-13 present now, known (seen at or before t), min(age, 20)/10 (frames since last seen)
    14-27 two nearest static segments: (dx, dy)/5 to the nearest point, clearance, unit tangent,
          closing speed/5, frames to contact/5 (1 = not within 5 frames)
    28-31 hidden now, outside now, hidden next, outside next (constant-velocity guess for t+1)

and of ``rel`` (``REL = 9`` per ordered pair k -> j, other object j seen from object k)::

    (dx, dy)/5, (dvx, dvy)/5, distance/5, gap (clipped to [-1, 3]), closing speed/5,
    frames to contact/5, j known
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.io.batch import Batch
from voe.models import statelik as sl

D = 32
REL = 9
LAYOUT_VERSION = 2


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


def _contact(gap: np.ndarray, closing: np.ndarray, dt: float) -> np.ndarray:
    """Frames until contact at the current closing speed, /5 and capped at 1."""
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(closing > 1e-3, np.maximum(gap, 0) / np.maximum(closing, 1e-3) / dt, 5.0)
    return np.minimum(f, 5.0) / 5


def _statics(x: np.ndarray, y: np.ndarray, half: np.ndarray, vx: np.ndarray, vy: np.ndarray,
             dt: float, geo: dict[str, Any]) -> np.ndarray:
    """``(..., 14)``: the two nearest segments' offset, clearance, tangent and time to contact."""
    feats = []
    for s in geo.get("statics", []):
        ax, ay = s["a"]
        bx, by = s["b"]
        sx, sy = bx - ax, by - ay
        L2 = max(sx * sx + sy * sy, 1e-12)
        h = np.clip(((x - ax) * sx + (y - ay) * sy) / L2, 0, 1)
        dx, dy = ax + h * sx - x, ay + h * sy - y
        clear = np.hypot(dx, dy) - s["radius"] - half
        L = np.sqrt(L2)
        tx, ty = (sx / L, sy / L) if sx >= 0 else (-sx / L, -sy / L)
        closing = (vx * dx + vy * dy) / np.maximum(np.hypot(dx, dy), 1e-6)
        feats.append(np.stack([dx / 5, dy / 5, clear, np.full_like(x, tx), np.full_like(x, ty),
                               closing / 5, _contact(clear, closing, dt)], -1))
    far = np.stack([np.full_like(x, 2.0), np.full_like(x, 2.0), np.full_like(x, 10.0),
                    np.zeros_like(x), np.zeros_like(x), np.zeros_like(x), np.ones_like(x)], -1)
    while len(feats) < 2:
        feats.append(far)
    allf = np.stack(feats, -2)  # (..., S, 7)
    order = np.argsort(allf[..., 2], axis=-1)[..., :2]  # two smallest clearances
    best = np.take_along_axis(allf, order[..., None], axis=-2)  # (..., 2, 7)
    best[..., 2] = np.clip(best[..., 2], -1, 3)
    return best.reshape(*x.shape, 14)


def _pairs(m: np.ndarray, ix: dict[str, int], half: np.ndarray, known: np.ndarray, dt: float) -> np.ndarray:
    """``(B, T, K, K, REL)`` features of other object j seen from object k (see module docstring)."""
    pos = np.stack([m[..., ix["x"]], m[..., ix["y"]]], -1)  # (B, T, K, 2)
    vel = np.stack([m[..., ix["vx"]], m[..., ix["vy"]]], -1)
    dp = pos[:, :, None] - pos[:, :, :, None]  # (B, T, K, K, 2): [k, j] = pos[j] - pos[k]
    dv = vel[:, :, None] - vel[:, :, :, None]
    dist = np.linalg.norm(dp, axis=-1)  # (B, T, K, K)
    gap = dist - half[:, :, None] - half[:, :, :, None]
    closing = -(dp * dv).sum(-1) / np.maximum(dist, 1e-6)
    kj = np.broadcast_to(known[:, :, None], dist.shape)
    rel = np.concatenate([dp / 5, dv / 5, (dist / 5)[..., None], np.clip(gap, -1, 3)[..., None],
                          (closing / 5)[..., None], _contact(gap, closing, dt)[..., None],
                          kj[..., None].astype(np.float64)], -1)
    eye = np.eye(known.shape[-1], dtype=bool)
    rel[..., eye, :] = 0.0
    rel[~(kj & known[:, :, :, None])] = 0.0
    return rel


def slot_features(batch: Batch) -> dict[str, np.ndarray]:
    """Inputs and targets of the learned state models for a batch.

    Returns:
        ``x`` (B, T, K, D) float32 inputs at t; ``rel`` (B, T, K, K, REL) pair inputs; ``mem`` (B, T, K, 9) memory CONT at t;
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
        x[b, ..., 14:28] = _statics(m[b, ..., ix["x"]], m[b, ..., ix["y"]], np.maximum(hx[b], hy[b]),
                                    m[b, ..., ix["vx"]], m[b, ..., ix["vy"]], batch.dt, geo)
        hid, out = _hidden_outside(m[b, ..., ix["x"]], m[b, ..., ix["y"]], hx[b], hy[b], geo)
        x[b, ..., 28], x[b, ..., 29] = hid, out
        hid, out = _hidden_outside(nxt[b, ..., ix["x"]], nxt[b, ..., ix["y"]], hx[b], hy[b], geo)
        x[b, ..., 30], x[b, ..., 31] = hid, out
    x[~known] = 0.0
    obs = np.nan_to_num(states[..., idx])
    rel = _pairs(m, ix, np.maximum(hx, hy), known, batch.dt)
    return {"x": x.astype(np.float32), "rel": rel.astype(np.float32), "mem": mem[..., idx].astype(np.float32),
            "base": nxt[..., idx].astype(np.float32), "known": known, "present": batch.present.copy(),
            "obs": obs.astype(np.float32),
            "circle": np.nan_to_num(states[..., ix["is_circle"]]) > 0.5}


def layout(batch: Batch) -> dict[str, Any]:
    """What a checkpoint of a state model records about its inputs."""
    return {"feature_names": list(batch.feature_names), "n_slots": int(batch.states.shape[2]),
            "input_dim": D, "pair_dim": REL, "layout_version": LAYOUT_VERSION}
