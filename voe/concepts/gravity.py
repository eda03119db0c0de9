"""Gravity: what goes up comes down, and what is dropped falls, on time.

A screen hangs in the air (its bottom above the floor, its top below the window's top), so a
ball is hidden while it is inside that column. Possible A: a ball is thrown straight up from the
floor into the column; it rises behind the screen, turns round and falls back out of the bottom
(after about 1 s). Possible B: the same ball is dropped from above the column; it falls in at the
top and out at the bottom, faster and much sooner. The balls share x, so while both are behind
the screen A's and B's frames are identical. Impossible AB / BA splice A and B in the middle of
those frames: the ball thrown up comes back down far too soon and too fast (AB), and the dropped
ball hangs behind the screen and comes out late and slowly (BA). Only gravity fixes when and how
fast a ball comes out of the column, so only gravity tells the spliced clips from the possible
ones.

Occluded (verdict): the splice falls with the ball hidden for at least 2 frames on each side:
F+M+T2+P+V+H+D. Perceptual: no screen; the ball jumps from one path to the other in view.

v2 (a pair: gravity switched off at the top of an arc) had the impossible object higher than the
possible one after the onset: a mean-height scorer passed it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import FLOOR_Y, G, common_hidden, floor, middle_splice
from voe.sim.rollout import Recording, simulate
from voe.sim.scene import Body, Occluder, Scene


class Gravity(Concept):
    name = "gravity"
    version = 3
    kind = "quadruplet"
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        h = look["height"]
        bottom = FLOOR_Y + self.uniform(rng, r["screen_bottom"])
        top = bottom + self.uniform(rng, r["screen_height"])
        apex = bottom + (top - bottom - h) * self.uniform(rng, r["apex_frac"])  # ball bottom at the top
        y_thrown = FLOOR_Y + h / 2  # resting on the floor when thrown
        return {"main_slots": list(ctx.slots[:1]), "look": look, "x": self.uniform(rng, r["x"]),
                "screen_bottom": bottom, "screen_top": top,
                "y_thrown": y_thrown, "vy_thrown": float(np.sqrt(2 * G * (apex - (y_thrown - h / 2)))),
                "y_dropped": top + self.uniform(rng, r["drop_gap"]) + h / 2,
                "screen_width": look["width"] + self.uniform(rng, r["screen_margin"])}

    def build(self, p: dict[str, Any], ctx: Context, thrown: bool) -> Scene:
        """The scene with the ball thrown up from the floor (A) or dropped from above (B)."""
        look = p["look"]
        ball = Body(slot=ctx.slots[0], shape=look["shape"], width=look["width"], height=look["height"],
                    x=p["x"], y=p["y_thrown"] if thrown else p["y_dropped"],
                    vy=p["vy_thrown"] if thrown else 0.0, friction=0.0, elasticity=0.2,
                    intensity=look["intensity"])
        half, pad = p["screen_width"] / 2, ctx.pixel
        occ = [] if ctx.visible else [Occluder(p["x"] - half - pad, p["screen_bottom"] - pad,
                                               p["x"] + half + pad, p["screen_top"] + pad)]
        return self.scene(ctx, [ball], [floor(friction=0.0, elasticity=0.3)], occ)

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        a, b = (simulate(self.build(p, ctx, thrown), ctx.cfg) for thrown in (True, False))
        slot = ctx.slots[0]
        if ctx.visible:  # where the two paths are closest, while the dropped ball is in the air
            ya, yb = a.states[:, slot, 1], b.states[:, slot, 1]  # (T,)
            falling = np.flatnonzero(b.states[:, slot, 4] < -0.5)
            s = int(falling[np.argmin(np.abs(ya - yb)[falling])]) if falling.size else 0
            if not 3 <= s <= ctx.cfg.n_frames - 3:
                raise ValueError("gravity: the two paths never come close; adjust the ranges in spec.yaml")
        else:
            s = middle_splice(common_hidden(a, b, [slot]), f"{self.id} behind the screen")
        return a, b, np.arange(ctx.cfg.n_frames) >= s
