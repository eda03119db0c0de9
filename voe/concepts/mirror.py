"""The left-right mirror of a clip, exact on the stored bytes (the ``mirrored`` set kind).

Why: a design that makes the impossible clip move the other way from the possible one (a time
reversal reverses the sideways drift) hands every scorer that is not mirror-symmetric a cue that
is not the concept: on Energy-v4, seed 4418, all ten random pixel networks were off chance, each
set's sign following the possible clip's horizontal velocity (``probes/energy/README.md``). A
set that holds each clip together with its mirror has every signed horizontal step and velocity
on both sides, so any statistic of direction ties exactly (balance level ``X``,
``voe.io.balance``).

Exact means: the mirrored states negate every horizontal step and velocity bit for bit, and every
frame is drawn from the stored states (``voe.sim.render.render_clip``, as ``voe probes export``
redraws it), so frames and states agree. ``extent - x`` is not exact in float32 for every ``x``
(below half the extent it rounds), so positions are first put on a grid of ``2**-16`` scene units
(``to_grid``, 1/10,000 of a pixel at 64 pixels), on which both ``extent - x`` and every
difference are exact; the clip is then redrawn from the rounded states. A frame depends on
positions, angle and looks only, not on velocities, so a clip and its time reversal still hold
the same frames.
"""

from __future__ import annotations

import numpy as np

from voe.sim.render import render_clip
from voe.sim.rollout import Recording
from voe.sim.scene import FEATURE_NAMES

#: Grid of stored horizontal positions: far below a pixel (0.156 units at 64 px) and below any
#: noise a model fits (the oracle's floor is 0.001), coarse enough that ``extent - x`` and the
#: differences of positions below 256 units are exact in float32 (8 + 16 bits of 24).
GRID = 2.0 ** -16
_X = FEATURE_NAMES.index("x")
#: Features a left-right mirror negates (horizontal velocity, and the sense of rotation).
_ODD = [FEATURE_NAMES.index(n) for n in ("angle", "vx", "omega")]


def to_grid(rec: Recording, size: int) -> Recording:
    """``rec`` with horizontal positions rounded to ``GRID`` (NaN stays NaN), redrawn at ``size``.

    Rounding commutes with time reversal (it touches positions only), so a clip and its
    reversal may be put on the grid in either order.
    """
    st = rec.states.copy()  # (T, K, F)
    st[..., _X] = (np.round(st[..., _X].astype(np.float64) / GRID) * GRID).astype(np.float32)
    return Recording(render_clip(st, rec.present, rec.geometry, size), st, rec.present.copy(),
                     rec.exists.copy(), rec.geometry)


def _mirror_geometry(geometry: dict, extent: float) -> dict:
    out = dict(geometry)
    out["occluders"] = [{**o, "x0": extent - o["x1"], "x1": extent - o["x0"]}
                        for o in geometry.get("occluders", [])]
    statics = []
    for s in geometry.get("statics", []):
        a, b = [extent - s["a"][0], s["a"][1]], [extent - s["b"][0], s["b"][1]]
        statics.append({**s, "a": b, "b": a} if b[0] < a[0] else {**s, "a": a, "b": b})
    out["statics"] = statics
    return out


def mirror(rec: Recording, size: int) -> Recording:
    """The clip flipped left to right about the window's centre (``x -> extent - x``), drawn at
    ``size`` pixels.

    Raises:
        ValueError: a position off ``GRID`` (call ``to_grid`` first): its mirror would not be exact.
    """
    extent = float(rec.geometry.get("extent", [10.0, 10.0])[0])
    st = rec.states.copy()  # (T, K, F)
    x = st[..., _X]
    on = ~np.isnan(x)
    if not np.array_equal(np.round(x[on].astype(np.float64) / GRID) * GRID, x[on].astype(np.float64)):
        raise ValueError("mirror: horizontal positions are not on the grid; call to_grid first")
    st[..., _X] = np.float32(extent) - x
    st[..., _ODD] = -st[..., _ODD]
    st += 0.0  # no negative zeros
    geometry = _mirror_geometry(rec.geometry, extent)
    return Recording(render_clip(st, rec.present, geometry, size), st, rec.present.copy(),
                     rec.exists.copy(), geometry)
