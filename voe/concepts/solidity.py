"""Solidity: objects do not pass through shelves or walls.

Two events, drawn per set. Shelf: an object is dropped onto a shelf above the floor; possible, it
lands and rests there; impossible, from the frame it touches the shelf it passes through and lands
on the floor below. Wall: an object is thrown at a tall wall; possible, it bounces back; impossible,
it flies through and falls on the far side. The impossible object stops colliding with static
geometry just before contact and collides again once it has fully cleared the barrier, so it
still lands on the floor. Occluded variant: the contact point is behind a screen (a band around the
shelf, or a screen in front of the wall's lower part) and the outcome is seen afterwards, the
object coming out under the band or on the far side of the wall. Visible variant: no screen.

Pair, not splice: a splice of two possible clips with the same barrier teleports the object
between their trajectories; it never shows an object moving continuously through the barrier.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.branch import edited, first_difference, pair, rollout
from voe.concepts.parts import FLOOR_Y, G, floor
from voe.sim.rollout import Recording
from voe.sim.scene import Body, Occluder, Scene, Segment
from voe.sim.world import World

BAR_R = 0.1  # shelf / wall half thickness
TOP = 7.2  # the main event stays below the distractor lane


class Solidity(Concept):
    name = "solidity"
    version = 1
    kind = "pair"
    confounded = True  # a branch pair: impossible frames are new (see probes/README)

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        event = "shelf" if rng.random() < 0.5 else "wall"
        direction = 1 if rng.random() < 0.5 else -1
        p: dict[str, Any] = {"main_slots": list(ctx.slots[:1]), "look": look, "event": event,
                             "direction": direction,
                             "elasticity": self.uniform(rng, r["elasticity"])}
        w, h = look["width"], look["height"]
        if event == "shelf":
            ys = self.uniform(rng, r["shelf_y"])
            drop = min(self.uniform(rng, r["drop"]), TOP - ys - BAR_R - h)
            vx = direction * self.uniform(rng, r["drift"])
            x_land = self.uniform(rng, r["centre_x"])
            t_fall = np.sqrt(2 * drop / G)
            screen_w = w + self.uniform(rng, r["screen_margin"])
            length = max(screen_w, w) + self.uniform(rng, r["shelf_extra"])
            p.update(shelf_y=ys, shelf_x=[x_land - length / 2, x_land + length / 2],
                     x0=x_land - vx * t_fall, y0=ys + BAR_R + drop + h / 2, vx=vx, vy=0.0,
                     screen=[x_land - screen_w / 2, ys - BAR_R - self.uniform(rng, [0.3, 0.5]),
                             x_land + screen_w / 2, ys + BAR_R + h + self.uniform(rng, [0.4, 0.7])])
        else:
            wx = self.uniform(rng, r["centre_x"])
            speed = self.uniform(rng, r["speed"])
            t_hit = self.uniform(rng, r["t_hit"])
            vy_hit = self.uniform(rng, r["vy_hit"])
            yc = FLOOR_Y + self.uniform(rng, r["hit_bottom"]) + h / 2
            vy0 = vy_hit + G * t_hit
            y0 = yc - vy0 * t_hit + 0.5 * G * t_hit**2
            lift = max(0.0, FLOOR_Y + 0.2 - (y0 - h / 2))  # never start inside the floor
            y0, yc = y0 + lift, yc + lift
            x_hit = wx - direction * (BAR_R + w / 2)
            margin = self.uniform(rng, r["screen_margin"]) / 2
            scr_top = yc + h / 2 + self.uniform(rng, [0.5, 0.8])
            wall_top = min(TOP, max(self.uniform(rng, r["wall_top"]), scr_top + 0.6, yc + h / 2 + 1.0))
            p.update(wall_x=wx, wall_top=wall_top, x0=x_hit - direction * speed * t_hit, y0=y0,
                     vx=direction * speed, vy=vy0,
                     screen=[wx - (w + BAR_R + margin), FLOOR_Y - 0.3, wx + w + BAR_R + margin, scr_top])
        return p

    def build(self, p: dict[str, Any], ctx: Context) -> Scene:
        """The clip's scene (also used by tests to locate the barrier)."""
        look = p["look"]
        obj = Body(slot=ctx.slots[0], shape=look["shape"], width=look["width"], height=look["height"],
                   x=p["x0"], y=p["y0"], vx=p["vx"], vy=p["vy"], friction=0.5,
                   elasticity=p["elasticity"], intensity=look["intensity"])
        if p["event"] == "shelf":
            x0, x1 = p["shelf_x"]
            bar = Segment((x0, p["shelf_y"]), (x1, p["shelf_y"]), BAR_R, 0.5, 0.5, "shelf")
        else:
            bar = Segment((p["wall_x"], FLOOR_Y), (p["wall_x"], p["wall_top"]), BAR_R, 0.0, 0.8, "wall")
        occ = [] if ctx.visible else [Occluder(*p["screen"])]
        return self.scene(ctx, [obj], [floor(friction=0.5), bar], occ)

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        slot = ctx.slots[0]
        scene = self.build(p, ctx)
        possible = rollout(scene, ctx.cfg)
        # the ghost ignores static geometry from the start; it leaves the possible path at contact
        _, ghost = rollout(scene, ctx.cfg, edited(0, lambda w: w.set_passable(slot, True, False)))
        contact = first_difference(possible[1][:, slot, :6], ghost[:, slot, :6])
        if contact < 2 or contact >= ctx.cfg.n_frames - 4:
            raise ValueError(f"solidity: contact at frame {contact}; adjust the ranges in spec.yaml")

        def cleared(world: World) -> bool:
            lo, hi = world.bboxes()[slot]
            if p["event"] == "shelf":
                return hi[1] < p["shelf_y"] - BAR_R - 0.02
            edge = p["wall_x"] + p["direction"] * (BAR_R + 0.02)
            return lo[0] > edge if p["direction"] > 0 else hi[0] < edge

        def restore(t: int, world: World) -> None:
            if cleared(world):
                world.set_passable(slot, statics=False, objects=False)

        hook = edited(contact - 1, lambda w: w.set_passable(slot, statics=True, objects=False), restore)
        return pair(scene, ctx.cfg, hook, f"{self.id} {p['event']}", possible)
