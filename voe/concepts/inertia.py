"""Inertia: an object sliding on a frictionless floor keeps its speed and direction.

Possible A: an object slides at velocity ``v1``. Possible B: the same object slides at ``v2``,
either at a clearly different speed in the same direction or in the reverse direction. Both are
timed to pass the same point ``x*`` at frame ``t0 - 1``, so the spliced clips (mask ``t >= t0``)
are continuous in position, ``x_AB[t0] - x_AB[t0 - 1] = v2 dt``, while the velocity jumps from
``v1`` to ``v2`` at ``t0``: AB and BA speed up, slow down or turn round on their own. ``t0`` is
also the first frame whose pixels differ from A. A screen stands in both clips. Occluded
variant: ``x*`` is behind the screen and the object is hidden at ``t0 - 1`` and ``t0``, so it
comes out too early, too late or on the side it went in. Visible variant: ``x*`` is in plain view,
away from the screen.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import floor, on_floor, screen
from voe.sim.rollout import Recording, simulate

CHANGES = ("speed", "reverse")


class Inertia(Concept):
    name = "inertia"
    version = 1
    kind = "quadruplet"
    # in view the object is at nearly the same place in A and B just before the onset, but not to
    # the pixel (two simulations), so the per-step change is not exactly balanced: perceptual
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        change = str(rng.choice(CHANGES))
        look = self.random_look(rng)
        s = look["width"]
        direction = 1 if rng.random() < 0.5 else -1
        if change == "speed":
            slow = self.uniform(rng, r["slow_speed"])
            speeds = [slow, slow * self.uniform(rng, r["speed_ratio"])]
            if rng.random() < 0.5:  # A is the fast one half of the time
                speeds.reverse()
            v1, v2 = direction * speeds[0], direction * speeds[1]
        else:
            v1 = direction * self.uniform(rng, r["reverse_speed"])
            v2 = -v1 * self.uniform(rng, r["reverse_ratio"])
        key = "onset_occluded" if not ctx.visible else "onset_visible"
        t0 = int(rng.integers(r[key][0], r[key][1] + 1))
        dt = ctx.cfg.dt
        width = s + self.uniform(rng, r["screen_margin"])
        if ctx.visible:
            x_star = self.uniform(rng, r["x_star_visible"])
            side = 1 if rng.random() < 0.5 else -1
            sx = 5.0 + side * self.uniform(rng, r["screen_offset_visible"])
        else:
            sx = self.uniform(rng, r["screen_x"])
            # centre the positions at t0 - 1 (x*) and t0 (x* + v dt, both clips) on the screen
            steps = [0.0, v1 * dt, v2 * dt]
            x_star = sx - (max(steps) + min(steps)) / 2
        return {"change": change, "look": look, "v1": v1, "v2": v2, "onset": t0,
                "x_star": x_star, "t_star": t0 - 1, "screen_x": sx, "screen_width": width,
                "screen_height": look["height"] + 0.9}

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        slot = ctx.slots[0]
        occ = [screen(p["screen_x"], p["screen_width"], p["screen_height"], pad=ctx.pixel)]
        dt = ctx.cfg.dt
        a, b = (simulate(self.scene(ctx, [on_floor(p["look"], slot, start_x(p, v, dt), v)],
                                    [floor()], occ), ctx.cfg)
                for v in (p["v1"], p["v2"]))
        return a, b, np.arange(ctx.cfg.n_frames) >= p["onset"]


def start_x(p: dict[str, Any], v: float, dt: float) -> float:
    """Start position so that an object at constant velocity ``v`` is at ``x*`` at ``t_star``."""
    return p["x_star"] - v * p["t_star"] * dt
