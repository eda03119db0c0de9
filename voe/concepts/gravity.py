"""Gravity: what is thrown up comes back down, on time.

A screen hangs in the air (its bottom above the floor, its top below the distractor lane), so a
ball is hidden while it is inside that column. Possible A: a ball is thrown straight up from the
floor; it rises into the column, turns round behind the screen and falls back out of its bottom
at the speed it went in, and lands. Possible B: the same throw ``shift`` frames later. While both
balls are behind the screen A's and B's frames are identical. Impossible AB / BA splice A and B
in the middle of those frames: the ball comes back down ``shift`` frames too late (AB: it hung in
the air) or too early (BA: it turned round below the height its speed carries it to).

Why this design (v4): in all four clips the ball leaves the column where it went in, at the speed
it went in with, moving down; only *when* differs, and how long a ball thrown up at a given speed
stays up is fixed by gravity alone (``2 v / g`` from the screen's bottom back to it). A smooth
track (a statistic of second differences across the screen) sees the same reversal in every
clip; v3's second possible clip (a ball dropped from above) came out much faster than the thrown
one went in, so its splices left a velocity jump that a smoothness statistic scored 1.00 on.
The speed going in is seen, so the probe needs inertia (the ball keeps the speed it was seen
with) as well as gravity.

Occluded (verdict): the splice falls with the ball hidden for at least 2 frames on each side:
F+M+T2+P+V+H+D. Perceptual: no screen; the splice falls where A's falling ball and B's rising one
are closest, so the ball turns round in mid-air in view.
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
    version = 4
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
        return {"main_slots": list(ctx.slots[:1]), "look": look, "x": self.uniform(rng, r["x"]),
                "screen_bottom": bottom, "screen_top": top,
                "vy_thrown": float(np.sqrt(2 * G * (apex - FLOOR_Y))),
                "shift": int(rng.integers(r["shift"][0], r["shift"][1] + 1)),
                "screen_width": look["width"] + self.uniform(rng, r["screen_margin"])}

    def build(self, p: dict[str, Any], ctx: Context, start: tuple[float, float] | None = None) -> Scene:
        """The throw of B (thrown from the floor at frame 0), or with ``start`` (height, vertical
        speed) the clip starting with the ball that far into its flight (A)."""
        look = p["look"]
        y, vy = start if start is not None else (FLOOR_Y + look["height"] / 2, p["vy_thrown"])
        ball = Body(slot=ctx.slots[0], shape=look["shape"], width=look["width"], height=look["height"],
                    x=p["x"], y=y, vy=vy, friction=0.0, elasticity=0.2, intensity=look["intensity"])
        half, pad = p["screen_width"] / 2, ctx.pixel
        occ = [] if ctx.visible else [Occluder(p["x"] - half - pad, p["screen_bottom"] - pad,
                                               p["x"] + half + pad, p["screen_top"] + pad)]
        return self.scene(ctx, [ball], [floor(friction=0.0, elasticity=0.3)], occ)

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        slot = ctx.slots[0]
        b = simulate(self.build(p, ctx), ctx.cfg)
        # A is B's throw `shift` frames on: started from B's simulated state at that frame (still in
        # view below the screen), so A's flight is B's frame for frame, not a re-integration of it
        st = b.states[p["shift"], slot].astype(np.float64)  # (F,)
        if not b.present[p["shift"], slot]:
            raise ValueError("gravity: the ball is hidden before frame `shift`; lower shift in spec.yaml")
        a = simulate(self.build(p, ctx, (float(st[1]), float(st[4]))), ctx.cfg)
        if ctx.visible:  # where A's falling ball and B's rising one are closest
            ya, yb = a.states[:, slot, 1], b.states[:, slot, 1]  # (T,)
            both = np.flatnonzero((a.states[:, slot, 4] < 0) & (b.states[:, slot, 4] > 0))
            both = both[: int(np.argmax(np.diff(np.append(both, -9)) != 1)) + 1]  # at the top, not at rest
            s = int(both[np.argmin(np.abs(ya - yb)[both])]) if both.size else 0
            if not 3 <= s <= ctx.cfg.n_frames - 3:
                raise ValueError("gravity: the two paths never cross in flight; adjust the ranges in spec.yaml")
        else:
            s = middle_splice(common_hidden(a, b, [slot]), f"{self.id} behind the screen")
        return a, b, np.arange(ctx.cfg.n_frames) >= s
