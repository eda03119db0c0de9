"""Solidity: objects do not pass through walls, so a hidden bounce takes the time the wall sets.

A wall stands on the floor; a screen hides its lower part (its top stands out above the screen, so
the wall is always in view), and the wall stands nearer the side the object comes from: the screen
reaches far beyond it (``far_side``). Possible A: an object slides along the frictionless floor towards
the wall, goes behind the screen, bounces off the wall and comes back out on the side it came
from. Possible B: the same event started ``shift`` frames later (the object starts ``speed *
shift * dt`` farther away). Both objects are behind the screen on a common run of frames, where
A's and B's frames are identical (only the screen and the wall's top show). Impossible AB / BA
splice A and B in the middle of that run: the object comes back ``shift`` frames too late (AB; it
lingered behind the screen) or too early (BA; it turned round before reaching the wall).

Why this design (v3): in every clip, possible or impossible, the object comes back out where it
went in, on the same side, at the same speed; only *when* differs. Where it went in is therefore
no help (v2's impossible objects came out on the far side: remembering where a hidden object went
in was enough to pass), and a smooth-track statistic sees the same jolt in all four clips. When
it comes back follows from its speed (inertia) and from where the wall stops it (solidity), both
needed. Without walls it would come out on the far side in every clip, so the splice is no
stranger than the possible clips.

Occluded (verdict): the splice falls with the object hidden for at least 2 frames on each side,
so the impossible pair holds exactly the frames, the per-step changes and the 3-frame windows of
the possible pair, and the same object positions, speeds and heights (F+M+T2+P+V+H+D).
Perceptual: no screen; the splice falls on A's first frame back off the wall, so the object
jumps back to B's approach in view (a change detector sees it).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import FLOOR_Y, common_hidden, floor, middle_splice, on_floor, screen
from voe.sim.rollout import Recording, simulate
from voe.sim.scene import Scene, Segment

BAR_R = 0.1  # wall half thickness


def far_side(d: float, e: float, v: float, shift: int, dt: float) -> float:
    """Screen beyond the wall's near face such that an object passing through the wall would show
    on the far side no sooner than one frame after the latest (AB's) return.

    Why: an observer without walls (``no-collisions``, constant velocity) expects the object out on
    the far side at ``t_far``. Where ``t_far`` falls between the early and the late return it pays
    for "not out yet" frames in the late splice only, and tells the splices from the possible clips
    without knowing walls (``no-collisions`` scored 0.75 on seed 0 with a 0.3-1.3 unit far side).
    With ``t_far`` after every return, no clip pays, whatever its return time. Wholly hidden at
    time 0, the object reaches the wall's face after ``d / v`` and is back at the near edge after
    ``d (1 + 1/e) / v``; passing through, its front shows past the far edge after
    ``(d + far) / v`` (``far`` from the wall's face).
    """
    return d / e + (shift + 1) * dt * v


class Solidity(Concept):
    name = "solidity"
    version = 3
    kind = "quadruplet"
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        w, h = look["width"], look["height"]
        side = -1 if rng.random() < 0.5 else 1  # the object comes from the left (-1) or the right
        speed = self.uniform(rng, r["speed"])
        e = self.uniform(rng, r["elasticity"])  # the wall's is 1: the restitution
        shift = int(rng.integers(r["shift"][0], r["shift"][1] + 1))
        d = self.uniform(rng, r["hidden_run"])  # travelled wholly hidden before touching the wall
        near = BAR_R + w + d  # wall centre to the screen's near edge
        far = far_side(d, e, speed, shift, ctx.cfg.dt) - BAR_R + self.uniform(rng, r["far_margin"])
        edge = 5.0 + side * (5.0 - self.uniform(rng, r["near_edge"]))  # from the window's edge
        wx = edge - side * near
        # A: wholly hidden after t_in seconds; B starts `shift` frames of travel farther away
        x_a = edge + side * (speed * self.uniform(rng, r["t_in"]) - w / 2)
        screen_h = h + self.uniform(rng, r["screen_above"])
        return {"main_slots": list(ctx.slots[:1]), "look": look, "side": side, "wall_x": wx,
                "wall_top": FLOOR_Y + screen_h + self.uniform(rng, r["wall_above"]),
                "speed": speed, "x_a": x_a, "shift": shift, "elasticity": e,
                "screen_x": wx + side * (near - far) / 2, "screen_width": near + far,
                "screen_height": screen_h + 0.3}

    def build(self, p: dict[str, Any], ctx: Context, late: bool) -> Scene:
        """The scene of A (``late=False``) or of B, the same event ``shift`` frames later."""
        side = p["side"]
        x0 = p["x_a"] + side * (p["speed"] * p["shift"] * ctx.cfg.dt if late else 0.0)
        obj = on_floor(p["look"], ctx.slots[0], x0, -side * p["speed"], elasticity=p["elasticity"])
        wall = Segment((p["wall_x"], FLOOR_Y), (p["wall_x"], p["wall_top"]), BAR_R, 0.0, 1.0, "wall")
        occ = [] if ctx.visible else [screen(p["screen_x"], p["screen_width"], p["screen_height"], pad=ctx.pixel)]
        return self.scene(ctx, [obj], [floor(), wall], occ)

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        a, b = (simulate(self.build(p, ctx, late), ctx.cfg) for late in (False, True))
        slot = ctx.slots[0]
        if ctx.visible:  # A's first frame back off the wall: B's object is still approaching
            vx = a.states[:, slot, 3] * p["side"]  # (T,) > 0 once it moves back
            s = int(np.argmax(np.nan_to_num(vx) > 0))
            if s == 0:
                raise ValueError("solidity: the object never bounces; adjust t_in/hidden_run in spec.yaml")
        else:
            s = middle_splice(common_hidden(a, b, [slot]), f"{self.id} behind the screen")
        return a, b, np.arange(ctx.cfg.n_frames) >= s
