"""Per-slot inputs of the object-centric model, computed in torch from the model's *own* slot state.

Why: the previous input code (``voe.models.features``) carried hidden objects forward at constant
velocity and flagged where that guess would be hidden. That is knowledge the network had not
learned, and random read-outs of it already separated the probes' hidden splices (random
``interaction`` networks were off chance, so every verdict of the architecture was confounded).
Here nothing is carried by hand: a slot's state is what was observed when it is visible, and
whatever the network itself predicted while it is not (``voe.models.interaction`` rolls hidden
slots forward). The inputs are plain geometry of that state: where it is, how it moves, its look,
the two nearest static segments and whether a screen covers it now. Nothing extrapolates.

Slot state ``z`` (per slot, ``Z = 11``): the nine ``CONT`` features (x, y, angle, vx, vy, omega,
width, height, intensity), ``circle`` (probability) and ``exist`` (1 once seen; for hidden slots
the model's own carried belief). ``lv`` (per slot, 9) is the log-variance of the carried state
(``LV_OBS`` when observed).

Layout of the slot input (``D = 29``)::

    0-1 x/10, y/10; 2-3 sin, cos(angle); 4-6 vx/5, vy/5, omega/5; 7-9 width, height, intensity
    10 circle, 11 exist, 12 observed now, 13-16 (lv of x, y, vx, vy + 9) / 10
    17-26 two nearest static segments: (dx, dy)/5 to the nearest point, clearance, unit tangent
    27 covered by a screen now, 28 outside the window now

and of the pair input (``REL = 7``, other slot j seen from slot k): (dx, dy)/5, (dvx, dvy)/5,
distance/5, gap (clipped to [-1, 3]), exist of j.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import torch

from voe.io.batch import Batch
from voe.models import statelik as sl

D, REL = 29, 7
LV_OBS = -12.0  # log-variance of an observed feature (far below the grid cell)
LV_NEW = 0.0  # log-variance of a never-seen slot's (meaningless) state
LAYOUT_VERSION = 3
MAX_STATICS, MAX_OCCLUDERS = 16, 6
_RANGE_LO = torch.tensor([a for a, _ in sl.RANGE[:6]] + [0.0, 0.0, 0.0])
_RANGE_HI = torch.tensor([b for _, b in sl.RANGE[:6]] + [3.0, 3.0, 1.5])


def _geometry_arrays(geo: dict[str, Any], where: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(MAX_STATICS, 6)`` segments (ax, ay, bx, by, radius, valid), ``(MAX_OCCLUDERS, 5)`` screens
    (x0, y0, x1, y1, valid) and the ``(2,)`` window extent of one clip."""
    st = np.zeros((MAX_STATICS, 6))
    occ = np.zeros((MAX_OCCLUDERS, 5))
    segs, scr = geo.get("statics", []), geo.get("occluders", [])
    if len(segs) > MAX_STATICS or len(scr) > MAX_OCCLUDERS:
        raise ValueError(f"{where}: {len(segs)} static segments and {len(scr)} screens; the interaction "
                         f"model takes at most {MAX_STATICS} and {MAX_OCCLUDERS}")
    for i, s in enumerate(segs):
        st[i] = (*s["a"], *s["b"], s["radius"], 1.0)
    for i, o in enumerate(scr):
        occ[i] = (o["x0"], o["y0"], o["x1"], o["y1"], 1.0)
    return st, occ, np.asarray(geo.get("extent", (10.0, 10.0)), dtype=np.float64)


def prepare(batch: Batch) -> dict[str, torch.Tensor]:
    """Observations and per-clip geometry as tensors, every one ``(B, T, ...)``.

    Geometry is repeated along time so that training can cut windows of any tensor alike
    (``voe.models.train._windows``); it is small (22 numbers per segment and screen per frame).
    """
    idx = sl.cont_index(batch.feature_names)
    B, T = batch.shape
    obs = np.nan_to_num(batch.states[..., idx].astype(np.float64))  # (B, T, K, 9)
    circle = np.nan_to_num(batch.states[..., batch.feature_names.index("is_circle")]) > 0.5
    geo = [_geometry_arrays(batch.geometry[b] if batch.geometry else {}, f"clip {b} of the batch")
           for b in range(B)]

    def rep(a: list[np.ndarray]) -> torch.Tensor:  # per clip (...) -> (B, T, ...)
        return torch.from_numpy(np.repeat(np.stack(a)[:, None], T, 1).astype(np.float32))

    return {"obs": torch.from_numpy(obs.astype(np.float32)), "present": torch.from_numpy(batch.present.copy()),
            "circle": torch.from_numpy(circle.astype(np.float32)),
            "statics": rep([g[0] for g in geo]), "occluders": rep([g[1] for g in geo]),
            "extent": rep([g[2] for g in geo]),
            "dt": torch.full((B, T), float(batch.dt), dtype=torch.float32)}


def layout(batch: Batch) -> dict[str, Any]:
    """What a checkpoint records about the inputs it was trained on."""
    return {"feature_names": list(batch.feature_names), "n_slots": int(batch.states.shape[2]),
            "input_dim": D, "pair_dim": REL, "layout_version": LAYOUT_VERSION}


def clamp_state(cont: torch.Tensor) -> torch.Tensor:
    """Keep a rolled-out state inside the observation range (a diverging rollout stays finite)."""
    return torch.maximum(torch.minimum(cont, _RANGE_HI.to(cont)), _RANGE_LO.to(cont))


def half_extents(cont: torch.Tensor, circle: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Axis-aligned half extents ``(B, K)`` of a (possibly rotated) box or a circle."""
    w, h = cont[..., 6].abs() / 2, cont[..., 7].abs() / 2
    c, s = torch.cos(cont[..., 2]).abs(), torch.sin(cont[..., 2]).abs()
    box = circle < 0.5
    return torch.where(box, c * w + s * h, w), torch.where(box, s * w + c * h, h)


def covered(cont: torch.Tensor, circle: torch.Tensor, occ: torch.Tensor,
            extent: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Whether a screen covers the whole object, and whether it is outside the window: ``(B, K)``.

    Args:
        cont: ``(B, K, 9)``; occ: ``(B, O, 5)``; extent: ``(B, 2)``.
    """
    hx, hy = half_extents(cont, circle)
    x, y = cont[..., 0], cont[..., 1]
    ex, ey = extent[:, None, 0], extent[:, None, 1]
    outside = (x + hx <= 0) | (x - hx >= ex) | (y + hy <= 0) | (y - hy >= ey)
    o = occ[:, None]  # (B, 1, O, 5)
    inside = ((o[..., 0] <= (x - hx)[..., None]) & ((x + hx)[..., None] <= o[..., 2])
              & (o[..., 1] <= (y - hy)[..., None]) & ((y + hy)[..., None] <= o[..., 3]) & (o[..., 4] > 0))
    return inside.any(-1), outside


def _statics(cont: torch.Tensor, half: torch.Tensor, st: torch.Tensor) -> torch.Tensor:
    """``(B, K, 10)``: offset, clearance and tangent of the two nearest valid segments."""
    x, y = cont[..., 0:1], cont[..., 1:2]  # (B, K, 1)
    a, b = st[:, None, :, 0:2], st[:, None, :, 2:4]  # (B, 1, S, 2)
    seg = b - a
    L2 = (seg * seg).sum(-1).clamp_min(1e-12)  # (B, 1, S)
    h = (((x - a[..., 0]) * seg[..., 0] + (y - a[..., 1]) * seg[..., 1]) / L2).clamp(0, 1)
    dx, dy = a[..., 0] + h * seg[..., 0] - x, a[..., 1] + h * seg[..., 1] - y  # (B, K, S)
    clear = torch.sqrt(dx * dx + dy * dy + 1e-12) - st[:, None, :, 4] - half[..., None]
    valid = st[:, None, :, 5] > 0
    clear = torch.where(valid, clear, torch.full_like(clear, 10.0))
    L = torch.sqrt(L2)
    sgn = torch.where(seg[..., 0] >= 0, 1.0, -1.0)
    tx, ty = (sgn * seg[..., 0] / L).expand_as(dx), (sgn * seg[..., 1] / L).expand_as(dx)
    f = torch.stack([dx / 5, dy / 5, clear.clamp(-1, 3), tx, ty], -1)  # (B, K, S, 5)
    f = torch.where(valid[..., None], f, torch.zeros_like(f))
    order = torch.topk(-clear, 2, dim=-1).indices  # (B, K, 2) nearest two
    best = torch.gather(f, 2, order[..., None].expand(*order.shape, 5))  # (B, K, 2, 5)
    return best.reshape(*cont.shape[:2], 10)


def slot_inputs(cont: torch.Tensor, circle: torch.Tensor, exist: torch.Tensor, lv: torch.Tensor,
                seen: torch.Tensor, geo: dict[str, torch.Tensor]) -> tuple[torch.Tensor, torch.Tensor]:
    """Slot inputs ``(B, K, D)`` and pair inputs ``(B, K, K, REL)`` of the slot state at one frame.

    Args:
        cont: ``(B, K, 9)``; circle, exist: ``(B, K)``; lv: ``(B, K, 9)``; seen: ``(B, K)`` observed
            now; geo: ``statics`` ``(B, S, 6)``, ``occluders`` ``(B, O, 5)``, ``extent`` ``(B, 2)``.
    """
    hx, hy = half_extents(cont, circle)
    hid, out = covered(cont, circle, geo["occluders"], geo["extent"])
    f = [cont[..., 0:1] / 10, cont[..., 1:2] / 10, torch.sin(cont[..., 2:3]), torch.cos(cont[..., 2:3]),
         cont[..., 3:6] / 5, cont[..., 6:9], circle[..., None], exist[..., None], seen[..., None].to(cont),
         (lv[..., [0, 1, 3, 4]] + 9) / 10, _statics(cont, torch.maximum(hx, hy), geo["statics"]),
         hid[..., None].to(cont), out[..., None].to(cont)]
    x = torch.cat(f, -1)
    pos, vel = cont[..., 0:2], cont[..., 3:5]
    dp = pos[:, None] - pos[:, :, None]  # (B, K, K, 2): [k, j] = pos[j] - pos[k]
    dv = vel[:, None] - vel[:, :, None]
    dist = torch.sqrt((dp * dp).sum(-1) + 1e-12)  # (B, K, K)
    half = torch.maximum(hx, hy)
    gap = dist - half[:, None] - half[:, :, None]
    exj = exist[:, None].expand_as(dist)
    rel = torch.cat([dp / 5, dv / 5, (dist / 5)[..., None], gap.clamp(-1, 3)[..., None], exj[..., None]], -1)
    return x, rel


def wrap(r: torch.Tensor) -> torch.Tensor:
    """Residuals ``(..., 9)`` with the angle wrapped to (-pi, pi]."""
    return torch.cat([r[..., :2], torch.remainder(r[..., 2:3] + math.pi, 2 * math.pi) - math.pi, r[..., 3:]], -1)
