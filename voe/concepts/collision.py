"""Collision: objects do not pass through each other; they meet, exchange momentum and part.

Two objects that look clearly different (one dim, one bright; a ball and a box of the same size,
so every hit is head-on and their masses are equal) slide towards each other on a frictionless
floor, with equal and opposite momentum, meet behind a screen (off its centre) and bounce back
out, each on its own side. Possible A: that event. Possible B: the same event ``shift`` frames
later (each object starts ``shift`` frames of travel farther away). While both objects are behind
the screen A's and B's frames are identical. Impossible AB / BA splice A and B in the middle of
those frames: the objects come back out ``shift`` frames too late (AB: they stuck together for a
while) or too early (BA: they turned round before they could have met, an action at a distance).

Why this design (v4): in all four clips each object comes back out where it went in, at the speed
its bounce gives it; only *when* differs. v3 spliced mirror images, so its impossible objects came
out on the far side: remembering where each hidden object went in (and that it stops there)
passed it (the ``no-inertia`` lesion scored 1.00). When the objects come back follows from where
and when they meet (inertia) and from their bouncing apart (collision): without collisions they
come out on the far side in every clip, without inertia they never come out at all.

Occluded (verdict): the splice falls with both objects hidden for at least 2 frames on each side:
F+M+T2+P+V+H+D. Perceptual: no screen; the splice falls on A's first frame after the hit, so the
objects jump back to B's approach in view.
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
    version = 4
    kind = "quadruplet"
    n_main = 2
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        size = self.uniform(rng, r["size"])  # both: the same mass, so the same speed and rebound
        shades = [self.uniform(rng, r["dim"]), self.uniform(rng, r["bright"])]
        if rng.random() < 0.5:
            shades.reverse()
        shapes = ["circle", "box"] if rng.random() < 0.5 else ["box", "circle"]
        looks = [{"shape": sh, "width": size, "height": size, "intensity": i}
                 for sh, i in zip(shapes, shades, strict=True)]
        # equal and opposite momentum: the centre of mass rests, both bounce back to their own side
        speed = self.uniform(rng, r["speed"])
        elasticity = [self.uniform(rng, r["elasticity"]) for _ in range(2)]
        shift = int(rng.integers(r["shift"][0], r["shift"][1] + 1))
        t_c = self.uniform(rng, r["t_contact"])
        centre = self.uniform(rng, r["centre_x"])
        offset = self.uniform(rng, r["screen_offset"])
        half = size + self.uniform(rng, r["hidden_run"]) + abs(offset)  # both hidden runs >= hidden_run
        return {"main_slots": list(ctx.slots[:2]), "looks": looks, "speeds": [speed, speed], "centre": centre,
                "screen_x": centre + offset, "shift": shift,
                "x_left": [centre - size / 2 - speed * t_c, centre + size / 2 + speed * t_c],
                "elasticity": elasticity, "screen_width": 2 * half,
                # the screen's foot is 0.3 below the floor's top: its top is screen_above over the objects
                "screen_height": size + 0.3 + self.uniform(rng, r["screen_above"])}

    def pass_through_margin(self, p: dict[str, Any], ctx: Context) -> float:
        """Seconds from the latest (AB's) return of either object to when, passing through the
        other, it would show past the screen's far edge; must be positive.

        Why: an observer without collisions (``no-collisions``, constant velocity) expects each
        object out on the far side at ``t_far``. Where ``t_far`` falls between the early and the
        late return it pays for "not out yet" frames in the late splice only, and tells the
        splices from the possible clips without knowing collisions (``no-collisions`` 0.75 on seed
        0 with objects of different mass and restitutions down to 0.64). Wholly hidden at time 0,
        an object ``d`` short of the meeting point is back at the near edge after ``d (1 + 1/e) /
        v`` (equal masses, equal speeds: each rebounds at ``e v``); passing through, its front
        shows past the far edge after ``(W - w) / v``.
        """
        w, v = p["looks"][0]["width"], p["speeds"][0]
        e = p["elasticity"][0] * p["elasticity"][1]
        W, off = p["screen_width"], p["screen_x"] - p["centre"]
        worst = np.inf
        for d in (W / 2 + off - w, W / 2 - off - w):  # each object's run to the meeting point
            t_ret = d * (1 + 1 / e) / v + p["shift"] * ctx.cfg.dt
            worst = min(worst, (W - w) / v - t_ret)
        return float(worst)

    def build(self, p: dict[str, Any], ctx: Context, late: bool) -> Scene:
        """The event of A (``late=False``) or of B, the same event ``shift`` frames later."""
        back = p["shift"] * ctx.cfg.dt if late else 0.0  # seconds of travel farther away
        xs = [p["x_left"][0] - p["speeds"][0] * back, p["x_left"][1] + p["speeds"][1] * back]
        vs = [p["speeds"][0], -p["speeds"][1]]
        bodies = [on_floor(look, ctx.slots[i], x, v, elasticity=e, mass=look["width"] * look["height"])
                  for i, (look, x, v, e) in enumerate(zip(p["looks"], xs, vs, p["elasticity"], strict=True))]
        occ = [] if ctx.visible else [screen(p["screen_x"], p["screen_width"], p["screen_height"], pad=ctx.pixel)]
        return self.scene(ctx, bodies, [floor(friction=0.0, elasticity=0.5)], occ)

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        if self.pass_through_margin(p, ctx) < ctx.cfg.dt:
            raise ValueError("collision: passing through, an object would show on the far side before the "
                             "late return; raise the elasticity or lower the speed in spec.yaml")
        a, b = (simulate(self.build(p, ctx, late), ctx.cfg) for late in (False, True))
        s1 = ctx.slots[0]
        if ctx.visible:  # A's first frame after the hit: object 1 moves back, B's still approach
            s = int(np.argmax(np.nan_to_num(a.states[:, s1, 3]) < 0))
            if s == 0:
                raise ValueError("collision: object 1 never bounces back; adjust the ranges in spec.yaml")
        else:
            s = middle_splice(common_hidden(a, b, ctx.slots[:2]), f"{self.id} behind the screen")
        return a, b, np.arange(ctx.cfg.n_frames) >= s
