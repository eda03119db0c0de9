"""Collision: objects do not pass through each other.

Two objects that look clearly different (one dim, one bright; a narrow and a wide box, or a ball
and a box; the same height, so every hit is head-on) slide towards each other on a frictionless
floor, with equal and opposite momentum, meet behind a screen at its centre and bounce back out,
each on its own side. Possible A: object 1 comes from the left, object 2 from the right. Possible
B: the mirror image (object 1 from the right, object 2 from the left). While both objects are
behind the screen A's and B's frames are identical. Impossible AB / BA splice A and B in the
middle of those frames: the objects go in one way round and come out the other way round, as if
they had passed through each other (their different looks show the swap).

Occluded (verdict): the splice falls with both objects hidden for at least 2 frames on each side:
F+M+T2+P+V+H+D. Perceptual: no screen; the splice falls just after contact, so the objects jump
to each other's side in view.

v2 (a pair: one object replayed passing through the other, or an action at a distance) showed
the impossible objects in places and at speeds the possible ones never had.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import common_hidden, floor, middle_splice, on_floor, screen
from voe.sim.rollout import Recording, simulate
from voe.sim.scene import Scene


class Collision(Concept):
    name = "collision"
    version = 3
    kind = "quadruplet"
    n_main = 2
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        sizes = [self.uniform(rng, r["small"]), self.uniform(rng, r["large"])]
        shades = [self.uniform(rng, r["dim"]), self.uniform(rng, r["bright"])]
        if rng.random() < 0.5:
            sizes.reverse()
        if rng.random() < 0.5:
            shades.reverse()
        height = self.uniform(rng, r["height"])
        shapes = [str(rng.choice(["circle", "box"])) for _ in range(2)]
        sizes = [height if sh == "circle" else s for sh, s in zip(shapes, sizes, strict=True)]
        looks = [{"shape": sh, "width": s, "height": height, "intensity": i}
                 for sh, s, i in zip(shapes, sizes, shades, strict=True)]
        # equal and opposite momentum (mass = area, the training world's law): the centre of mass
        # rests, so both objects bounce back, each to its own side
        momentum = self.uniform(rng, r["momentum"])
        speeds = [momentum / (s * height) for s in sizes]
        t_c = self.uniform(rng, r["t_contact"])
        centre = self.uniform(rng, r["centre_x"])
        margin = self.uniform(rng, r["screen_margin"])
        return {"main_slots": list(ctx.slots[:2]), "looks": looks, "speeds": speeds, "centre": centre,
                "x_left": [centre - sizes[0] / 2 - speeds[0] * t_c, centre + sizes[1] / 2 + speeds[1] * t_c],
                "elasticity": [self.uniform(rng, r["elasticity"]) for _ in range(2)],
                "screen_width": 2 * (max(sizes) + margin),
                # the screen's foot is 0.3 below the floor's top: its top is screen_above over the objects
                "screen_height": height + 0.3 + self.uniform(rng, r["screen_above"])}

    def build(self, p: dict[str, Any], ctx: Context, side: int) -> Scene:
        """Object 1 starts on the left (``side=-1``, A) or, mirrored, on the right (``+1``, B)."""
        c = p["centre"]
        xs = p["x_left"] if side < 0 else [2 * c - x for x in p["x_left"]]
        vs = [-side * p["speeds"][0], side * p["speeds"][1]]
        bodies = [on_floor(look, ctx.slots[i], x, v, elasticity=e, mass=look["width"] * look["height"])
                  for i, (look, x, v, e) in enumerate(zip(p["looks"], xs, vs, p["elasticity"], strict=True))]
        occ = [] if ctx.visible else [screen(c, p["screen_width"], p["screen_height"], pad=ctx.pixel)]
        return self.scene(ctx, bodies, [floor(friction=0.0, elasticity=0.5)], occ)

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        a, b = (simulate(self.build(p, ctx, side), ctx.cfg) for side in (-1, 1))
        s1 = ctx.slots[0]
        if ctx.visible:  # the first frame after the hit: object 1 moves back
            s = int(np.argmax(np.nan_to_num(a.states[:, s1, 3]) < 0))
            if s == 0:
                raise ValueError("collision: object 1 never bounces back; adjust the ranges in spec.yaml")
        else:
            s = middle_splice(common_hidden(a, b, ctx.slots[:2]), f"{self.id} behind the screen")
        return a, b, np.arange(ctx.cfg.n_frames) >= s
