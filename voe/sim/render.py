"""Anti-aliased grayscale rendering of a scene by signed distance fields.

Why: pixel models must see sub-pixel motion, so every shape is drawn with analytic coverage
``clip(0.5 - sd / pixel, 0, 1)`` instead of hard edges. Static segments and occluders do not
move, so they are rasterised once per clip into a background and a foreground layer; each frame
then draws only the dynamic objects between the two. Occluders are opaque and drawn last, so they
hide whatever is behind them.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from voe.sim.scene import Body, Occluder, Segment

BACKGROUND = 0.0
STATIC_INTENSITY = 0.45
OCCLUDER_INTENSITY = 0.25


class Renderer:
    """Draws frames of size ``(size, size)`` for the window ``[0, extent]``.

    Args:
        statics: static segments (drawn behind objects).
        occluders: screens (drawn in front of objects).
        extent: world window ``(width, height)`` in scene units.
        size: image side in pixels.
    """

    def __init__(self, statics: Iterable[Segment], occluders: Iterable[Occluder],
                 extent: tuple[float, float], size: int) -> None:
        self.size = size
        self.pix = extent[0] / size  # scene units per pixel (square pixels)
        ys, xs = np.mgrid[0:size, 0:size].astype(np.float64)
        self.px = (xs + 0.5) * (extent[0] / size)  # (H, W) world x of pixel centres
        self.py = extent[1] - (ys + 0.5) * (extent[1] / size)  # (H, W) world y, y up
        back = np.full((size, size), BACKGROUND)
        for seg in statics:
            cov = self._coverage(self._sd_segment(seg.a, seg.b, seg.radius))
            back = back * (1 - cov) + STATIC_INTENSITY * cov
        self.back = back  # (H, W)
        front = np.zeros((size, size))
        for occ in occluders:
            sd = self._sd_box((occ.x0 + occ.x1) / 2, (occ.y0 + occ.y1) / 2, 0.0,
                              (occ.x1 - occ.x0) / 2, (occ.y1 - occ.y0) / 2)
            front = np.maximum(front, self._coverage(sd))
        self.front = front  # (H, W) occluder coverage

    # -- signed distances (negative inside) -------------------------------------------------
    def _coverage(self, sd: np.ndarray) -> np.ndarray:
        return np.clip(0.5 - sd / self.pix, 0.0, 1.0)

    def _sd_circle(self, cx: float, cy: float, r: float) -> np.ndarray:
        return np.hypot(self.px - cx, self.py - cy) - r

    def _sd_box(self, cx: float, cy: float, angle: float, hx: float, hy: float) -> np.ndarray:
        c, s = np.cos(angle), np.sin(angle)
        dx, dy = self.px - cx, self.py - cy
        qx = np.abs(c * dx + s * dy) - hx  # rotate into the box frame
        qy = np.abs(-s * dx + c * dy) - hy
        outside = np.hypot(np.maximum(qx, 0), np.maximum(qy, 0))
        return outside + np.minimum(np.maximum(qx, qy), 0)

    def _sd_segment(self, a, b, r: float) -> np.ndarray:
        ax, ay = a
        bx, by = b
        vx, vy = bx - ax, by - ay
        denom = max(vx * vx + vy * vy, 1e-12)
        h = np.clip(((self.px - ax) * vx + (self.py - ay) * vy) / denom, 0, 1)
        return np.hypot(self.px - ax - h * vx, self.py - ay - h * vy) - r

    # -- frames -------------------------------------------------------------------------------
    def object_coverage(self, spec: Body, x: float, y: float, angle: float) -> np.ndarray:
        """Coverage ``(H, W)`` of one object at a pose."""
        if spec.shape == "circle":
            return self._coverage(self._sd_circle(x, y, spec.radius))
        return self._coverage(self._sd_box(x, y, angle, spec.width / 2, spec.height / 2))

    def frame(self, objects: Iterable[tuple[Body, float, float, float]]) -> np.ndarray:
        """Render one frame from ``(spec, x, y, angle)`` tuples; returns uint8 ``(H, W)``."""
        img = self.back.copy()
        for spec, x, y, angle in objects:
            cov = self.object_coverage(spec, x, y, angle)
            img = img * (1 - cov) + spec.intensity * cov
        img = img * (1 - self.front) + OCCLUDER_INTENSITY * self.front
        return np.round(img * 255.0).astype(np.uint8)
