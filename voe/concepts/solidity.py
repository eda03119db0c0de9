"""Solidity: objects do not pass through walls.

A wall stands on the floor; a screen hides its lower part (its top stands out above the screen, so
the wall is always in view). Possible A: an object slides along the frictionless floor from the
left, goes behind the screen, bounces off the wall and comes back out on the left. Possible B: the
mirror image, the object coming from the right and going back to the right. Both objects are
behind the screen on the same frames, where A's and B's frames are identical (only the screen and
the wall's top show). Impossible AB / BA splice A and B in the middle of those frames: the object
goes in on one side of the wall and comes out on the other, as if it had passed through it.

Occluded (verdict): the splice falls with the object hidden for at least 2 frames on each side, so
the impossible pair holds exactly the frames, the per-step changes and the 3-frame windows of the
possible pair, and the same object positions, speeds and heights (F+M+T2+P+V+H+D). Only the
history (which side it came from) and the outcome (which side it leaves on) disagree, and only
the wall makes them disagree. Perceptual: no screen; the splice falls at contact, so the object
jumps across the wall in view (a change detector sees it).

v1 (a pair: the object replayed with collisions switched off) showed the impossible object in
places the possible one never visits, and moving more: framecopy and a motion-energy scorer passed.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import FLOOR_Y, common_hidden, floor, middle_splice, on_floor, screen
from voe.sim.rollout import Recording, simulate
from voe.sim.scene import Scene, Segment

BAR_R = 0.1  # wall half thickness


class Solidity(Concept):
    name = "solidity"
    version = 2
    kind = "quadruplet"
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        w, h = look["width"], look["height"]
        wx = self.uniform(rng, r["wall_x"])
        speed = self.uniform(rng, r["speed"])
        t_hit = self.uniform(rng, r["t_hit"])
        screen_w = 2 * (BAR_R + w + self.uniform(rng, r["screen_margin"]))
        screen_h = h + self.uniform(rng, r["screen_above"])
        return {"main_slots": list(ctx.slots[:1]), "look": look, "wall_x": wx,
                "wall_top": FLOOR_Y + screen_h + self.uniform(rng, r["wall_above"]),
                "speed": speed, "x_left": wx - BAR_R - w / 2 - speed * t_hit,
                "elasticity": self.uniform(rng, r["elasticity"]),
                "screen_width": screen_w, "screen_height": screen_h + 0.3}

    def build(self, p: dict[str, Any], ctx: Context, side: int) -> Scene:
        """The scene with the object starting on the left (``side=-1``) or right (``+1``)."""
        x0 = p["x_left"] if side < 0 else 2 * p["wall_x"] - p["x_left"]
        obj = on_floor(p["look"], ctx.slots[0], x0, -side * p["speed"], elasticity=p["elasticity"])
        wall = Segment((p["wall_x"], FLOOR_Y), (p["wall_x"], p["wall_top"]), BAR_R, 0.0, 1.0, "wall")
        occ = [] if ctx.visible else [screen(p["wall_x"], p["screen_width"], p["screen_height"], pad=ctx.pixel)]
        return self.scene(ctx, [obj], [floor(), wall], occ)

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        a, b = (simulate(self.build(p, ctx, side), ctx.cfg) for side in (-1, 1))
        slot = ctx.slots[0]
        if ctx.visible:  # the first frame the object has come back off the wall
            vx = a.states[:, slot, 3]  # (T,)
            s = int(np.argmax(np.nan_to_num(vx) < 0))
            if s == 0:
                raise ValueError("solidity: the object never bounces; adjust t_hit in spec.yaml")
        else:
            s = middle_splice(common_hidden(a, b, [slot]), f"{self.id} behind the screen")
        return a, b, np.arange(ctx.cfg.n_frames) >= s
