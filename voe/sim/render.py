"""Anti-aliased rendering of clips from their stored states, at any size, grayscale or RGB.

Why: pixel models must see sub-pixel motion, so every shape is drawn with analytic coverage
``clip(0.5 - sd / pixel, 0, 1)`` of its signed distance ``sd`` instead of hard edges. A frame is
a pure function of what a probe set stores (the clip's ``states``, ``present`` and static
``geometry``): the generator draws exactly what it records, and ``voe probes export`` redraws
the same clips natively at 224 px or in colour without re-simulating anything.

Speed: statics and screens do not move, so they are rasterised once per (geometry, size) into a
background and a foreground layer (cached). Objects are drawn for all frames of a clip at once,
each in a small patch around it (``(n, P, P)`` pixels, not the whole image), slot after slot.
Screens are opaque and drawn last, so an object that is not ``present`` could not show anyway.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from voe.sim.scene import FEATURE_NAMES, N_FEATURES, Body, Occluder, Segment, geometry_from_dict

BACKGROUND = 0.0
STATIC_INTENSITY = 0.45
OCCLUDER_INTENSITY = 0.25
#: RGB mode: background, statics, screens, and object colours by slot (times the intensity).
RGB_BACKGROUND = (0.0, 0.0, 0.0)
RGB_STATIC = (0.55, 0.5, 0.42)
RGB_OCCLUDER = (0.22, 0.27, 0.4)
RGB_SLOTS = ((0.95, 0.3, 0.25), (0.3, 0.8, 0.3), (0.35, 0.55, 1.0), (1.0, 0.8, 0.2),
             (0.85, 0.4, 0.95), (0.2, 0.85, 0.85), (1.0, 0.55, 0.15), (0.8, 0.8, 0.8))
X, Y, ANGLE = (FEATURE_NAMES.index(n) for n in ("x", "y", "angle"))
IS_CIRCLE, WIDTH, HEIGHT, INTENSITY = (FEATURE_NAMES.index(n) for n in ("is_circle", "width", "height",
                                                                         "intensity"))


def half_extents(states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Half width and half height of each object's axis-aligned bounding box; ``states`` (..., F)."""
    hw, hh = 0.5 * states[..., WIDTH], 0.5 * states[..., HEIGHT]
    c, s = np.abs(np.cos(states[..., ANGLE])), np.abs(np.sin(states[..., ANGLE]))
    circle = states[..., IS_CIRCLE] > 0.5
    return np.where(circle, hw, c * hw + s * hh), np.where(circle, hh, s * hw + c * hh)


def visible(states: np.ndarray, occluders: Iterable[Occluder], extent: tuple[float, float],
            pixel: float) -> np.ndarray:
    """Which objects are visible: inside the window and not fully behind a screen, ``(...)`` bool.

    ``states`` (..., F) holds true poses (NaN where the object does not exist). An object within
    ``pixel`` of a screen's edge or of the window's border counts as visible: anti-aliasing shows it.
    """
    ex, ey = half_extents(states)
    x, y = states[..., X], states[..., Y]
    lo_x, hi_x, lo_y, hi_y = x - ex, x + ex, y - ey, y + ey
    with np.errstate(invalid="ignore"):
        out = (hi_x > pixel) & (lo_x < extent[0] - pixel) & (hi_y > pixel) & (lo_y < extent[1] - pixel)
        for o in occluders:
            m = pixel
            out &= ~((o.x0 + m <= lo_x) & (hi_x <= o.x1 - m) & (o.y0 + m <= lo_y) & (hi_y <= o.y1 - m))
    return out


_WORK: dict[tuple[int, ...], np.ndarray] = {}  # float32 work canvases by (T, H, W, C), shared


@dataclass
class _Patches:
    """Every present object of a clip, slot after slot: its patch pixels inside the image."""

    pix: np.ndarray  # (M,) flat pixel index into (H, W)
    idx: np.ndarray  # (M,) flat index into (T, H, W)
    cov: np.ndarray  # (M, 1) float32 coverage
    colour: np.ndarray  # (M, C) float32
    bounds: list[tuple[int, int]]  # per slot drawn, its [start, stop) in the flat arrays


class Renderer:
    """Draws frames of size ``(size, size)`` for the window ``[0, extent]``.

    Args:
        statics: static segments (drawn behind objects).
        occluders: screens (drawn in front of objects).
        extent: world window ``(width, height)`` in scene units.
        size: image side in pixels.
        rgb: colour frames ``(..., H, W, 3)`` with one colour per slot, else grayscale ``(..., H, W)``.
    """

    def __init__(self, statics: Iterable[Segment], occluders: Iterable[Occluder],
                 extent: tuple[float, float], size: int, rgb: bool = False) -> None:
        self.size, self.rgb, self.extent = size, rgb, (float(extent[0]), float(extent[1]))
        self.pix = extent[0] / size  # scene units per pixel (square pixels)
        ys, xs = np.mgrid[0:size, 0:size].astype(np.float64)
        px = (xs + 0.5) * self.pix  # (H, W) world x of pixel centres
        py = self.extent[1] - (ys + 0.5) * (extent[1] / size)  # (H, W) world y, y up
        c = 3 if rgb else 1
        back = np.empty((size, size, c))
        back[:] = RGB_BACKGROUND if rgb else BACKGROUND
        static = np.array(RGB_STATIC if rgb else (STATIC_INTENSITY,))
        for seg in statics:  # each shape only where it can cover a pixel (elsewhere coverage is 0)
            r, ((ax, ay), (bx, by)) = seg.radius, (seg.a, seg.b)
            w = self._window(min(ax, bx) - r, max(ax, bx) + r, min(ay, by) - r, max(ay, by) + r)
            cov = self._coverage(_sd_segment(px[w], py[w], seg.a, seg.b, r))[..., None]
            back[w] = back[w] * (1 - cov) + static * cov
        front = np.zeros((size, size, 1))
        for occ in occluders:
            w = self._window(occ.x0, occ.x1, occ.y0, occ.y1)
            sd = _sd_box(px[w], py[w], (occ.x0 + occ.x1) / 2, (occ.y0 + occ.y1) / 2, 0.0,
                         (occ.x1 - occ.x0) / 2, (occ.y1 - occ.y0) / 2)
            front[w] = np.maximum(front[w], self._coverage(sd)[..., None])
        occluder = np.array(RGB_OCCLUDER if rgb else (OCCLUDER_INTENSITY,))
        # (H, W, C) float32 layers; a pixel's value is rint(canvas * keep + cover) (screens on top)
        keep = np.broadcast_to(255.0 * (1 - front), back.shape)
        self._layers = (back.astype(np.float32), keep.astype(np.float32),
                        (255.0 * occluder * front).astype(np.float32))
        self._empty = np.rint(self._layers[0] * self._layers[1] + self._layers[2]).astype(np.uint8)

    def _window(self, x0: float, x1: float, y0: float, y1: float) -> tuple[slice, slice]:
        """Rows and columns of the pixels within two pixels of the box ``[x0, x1] x [y0, y1]``."""
        S, p, top = self.size, self.pix, self.extent[1]

        def bound(v: float) -> int:
            return min(max(int(v), 0), S)

        cols = slice(bound(math.floor(x0 / p) - 2), bound(math.ceil(x1 / p) + 2))
        rows = slice(bound(math.floor((top - y1) / p) - 2), bound(math.ceil((top - y0) / p) + 2))
        return rows, cols

    def _coverage(self, sd: np.ndarray) -> np.ndarray:
        return np.clip(0.5 - sd / self.pix, 0.0, 1.0)

    # -- clips -------------------------------------------------------------------------------
    def clip(self, states: np.ndarray, present: np.ndarray) -> np.ndarray:
        """Render a clip: ``states`` (T, K, F), ``present`` (T, K) -> uint8 (T, H, W[, 3]).

        Only present objects are drawn, in slot order (the draw order is part of the data). Work
        is done only in the patches that objects cover; elsewhere a frame is the empty scene.
        """
        T, K = present.shape
        k, t = np.nonzero(present.T)  # (N,) slot and frame of every present object, slot-major
        st = states[t, k].astype(np.float64)  # (N, F)
        S, C = self.size, self._empty.shape[-1]
        out = np.empty((T, S, S, C), dtype=np.uint8)
        out[:] = self._empty
        if len(t):
            work = _WORK.get((T, S, S, C))
            if work is None:
                work = _WORK[(T, S, S, C)] = np.zeros((T, S, S, C), dtype=np.float32)
            w, o = work.reshape(-1, C), out.reshape(-1, C)  # (T*H*W, C) views
            back, keep, cover = (x.reshape(-1, C) for x in self._layers)
            p = self._patches(t, k, st)
            w[p.idx] = back[p.pix]  # reset the patches to the background first: patches overlap
            for a, b in p.bounds:  # then blend the objects in slot order
                i, cov = p.idx[a:b], p.cov[a:b]
                w[i] = w[i] * (1 - cov) + p.colour[a:b] * cov
            v = w[p.idx] * keep[p.pix] + cover[p.pix]
            o[p.idx] = np.rint(v, out=v)
        return out if self.rgb else out[..., 0]

    def _patches(self, t: np.ndarray, k: np.ndarray, st: np.ndarray) -> _Patches:
        """Coverage of each object in a ``P x P`` patch around it; ``t``, ``k`` (N,), ``st`` (N, F).
        Patch pixels outside the image are dropped (they can reach no output)."""
        ex, ey = half_extents(st)  # (N,)
        P = int(np.ceil(2 * max(ex.max(), ey.max()) / self.pix)) + 3  # patch side
        x, y = st[:, X], st[:, Y]
        j0 = np.floor((x - ex) / self.pix - 1).astype(np.int64)  # first column the object can tint
        i0 = np.floor((self.extent[1] - y - ey) / self.pix - 1).astype(np.int64)
        r = np.arange(P)
        jj, ii = j0[:, None] + r, i0[:, None] + r  # (N, P)
        dx = (jj[:, None, :] + 0.5) * self.pix - x[:, None, None]  # (N, 1, P)
        dy = (self.extent[1] - (ii[:, :, None] + 0.5) * self.pix) - y[:, None, None]  # (N, P, 1)
        circle = st[:, IS_CIRCLE] > 0.5
        sd = np.empty((len(t), P, P))
        # boolean selection copies; when every object is of one kind a plain view does
        circ = slice(None) if circle.all() else circle if circle.any() else None
        box = slice(None) if circ is None else None if circle.all() else ~circle
        if circ is not None:
            dxc, dyc = dx[circ], dy[circ]  # sqrt, not hypot: libm's hypot is 20x slower here
            sd[circ] = np.sqrt(dxc * dxc + dyc * dyc) - 0.5 * st[circ, WIDTH, None, None]
        if box is not None:
            a = st[box, ANGLE, None, None]
            c, s = np.cos(a), np.sin(a)
            dxb, dyb = dx[box], dy[box]
            qx = np.abs(c * dxb + s * dyb) - 0.5 * st[box, WIDTH, None, None]
            qy = np.abs(-s * dxb + c * dyb) - 0.5 * st[box, HEIGHT, None, None]
            ox, oy = np.maximum(qx, 0), np.maximum(qy, 0)
            sd[box] = np.sqrt(ox * ox + oy * oy) + np.minimum(np.maximum(qx, qy), 0)
        colour = st[:, INTENSITY, None]  # (N, 1)
        if self.rgb:
            colour = colour * np.array(RGB_SLOTS)[k % len(RGB_SLOTS)]  # (N, 3)
        S = self.size
        inside = ((ii >= 0) & (ii < S))[:, :, None] & ((jj >= 0) & (jj < S))[:, None, :]  # (N, P, P)
        pix = (ii[:, :, None] * S + jj[:, None, :])[inside]  # (M,) flat pixel index in (H, W)
        per_object = inside.sum(axis=(1, 2))  # (N,)
        idx = np.repeat(t, per_object) * (S * S) + pix
        ends = np.cumsum(per_object)
        last = np.flatnonzero(np.r_[k[1:] != k[:-1], True])  # last object of each slot
        bounds = [(int(a), int(b)) for a, b in zip(np.r_[0, ends[last][:-1]], ends[last], strict=True)]
        cov = self._coverage(sd)[inside].astype(np.float32)[:, None]  # (M, 1)
        return _Patches(pix, idx, cov, np.repeat(colour, per_object, axis=0).astype(np.float32), bounds)

    # -- single frames (tests, figures) ---------------------------------------------------------
    def frame(self, objects: Iterable[tuple[Body, float, float, float]]) -> np.ndarray:
        """Render one frame from ``(spec, x, y, angle)`` tuples, drawn in the given order."""
        objects = list(objects)
        states = np.zeros((1, max(len(objects), 1), N_FEATURES))
        for k, (spec, x, y, angle) in enumerate(objects):
            states[0, k] = state_row(spec, x, y, angle)
        present = np.zeros(states.shape[:2], dtype=bool)
        present[0, : len(objects)] = True
        return self.clip(states, present)[0]


def state_row(spec: Body, x: float, y: float, angle: float, vx: float = 0.0, vy: float = 0.0,
              omega: float = 0.0) -> tuple[float, ...]:
    """One object's state features in ``FEATURE_NAMES`` order."""
    return (x, y, angle, vx, vy, omega, spec.shape == "circle", spec.shape == "box",
            spec.width, spec.height, spec.intensity)


def _sd_box(px, py, cx: float, cy: float, angle: float, hx: float, hy: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    dx, dy = px - cx, py - cy
    qx = np.abs(c * dx + s * dy) - hx  # rotate into the box frame
    qy = np.abs(-s * dx + c * dy) - hy
    return np.hypot(np.maximum(qx, 0), np.maximum(qy, 0)) + np.minimum(np.maximum(qx, qy), 0)


def _sd_segment(px, py, a, b, r: float) -> np.ndarray:
    (ax, ay), (bx, by) = a, b
    vx, vy = bx - ax, by - ay
    denom = max(vx * vx + vy * vy, 1e-12)
    h = np.clip(((px - ax) * vx + (py - ay) * vy) / denom, 0, 1)
    return np.hypot(px - ax - h * vx, py - ay - h * vy) - r


@lru_cache(maxsize=16)  # the clips of a set share one; 16 bound memory at 224 px RGB too
def renderer_cached(statics: tuple[Segment, ...], occluders: tuple[Occluder, ...],
                    extent: tuple[float, float], size: int, rgb: bool = False) -> Renderer:
    """A renderer shared by every clip with the same static geometry (the clips of a set)."""
    return Renderer(statics, occluders, extent, size, rgb)


def renderer_for(geometry: dict, size: int, rgb: bool = False) -> Renderer:
    """A (cached) renderer for a clip's stored geometry (``Scene.geometry()``)."""
    statics, occluders = geometry_from_dict(geometry)
    extent = tuple(float(e) for e in geometry.get("extent", (10.0, 10.0)))
    return renderer_cached(statics, occluders, extent, int(size), bool(rgb))


def render_clip(states: np.ndarray, present: np.ndarray, geometry: dict, size: int,
                rgb: bool = False) -> np.ndarray:
    """Frames of a stored clip: ``states`` (T, K, F), ``present`` (T, K) -> uint8 (T, H, W[, 3])."""
    return renderer_for(geometry, size, rgb).clip(states, present)
