"""Gravity: unsupported objects fall; they do not float.

Two events. Ledge (visible and occluded sets): an object slides along a frictionless shelf and
off its end; possible, it falls in a parabola to the floor; impossible, its gravity is switched off
on the last frame it is supported, so it carries on horizontally at shelf height (or drifts up).
Throw (visible sets only): an object flies in an arc; possible, it lands on the floor; impossible,
at a frame in mid-air it stops and hangs there or starts drifting up. Occluded variant: a screen
standing on the floor hides the shelf's end, so the object leaves its support behind the screen
and comes out on the far side at shelf height instead of low down. Visible variant: no screen.

Pair, not splice: the impossible path (level flight off a shelf, hanging in mid-air) is not a piece
of any possible clip in the same scene, so no splice of two possible clips shows it; a splice would
only make the object jump between two falling paths.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.branch import edited, pair, rollout
from voe.concepts.parts import FLOOR_Y, floor, pick
from voe.sim.rollout import Recording
from voe.sim.scene import Body, Occluder, Scene, Segment
from voe.sim.world import World

G = 9.81
BAR_R = 0.1


class Gravity(Concept):
    name = "gravity"
    version = 1
    kind = "pair"

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        w, h = look["width"], look["height"]
        direction = 1 if rng.random() < 0.5 else -1
        event = "ledge" if (not ctx.visible or rng.random() < 0.5) else "throw"
        p: dict[str, Any] = {"main_slots": list(ctx.slots[:1]), "look": look, "event": event,
                             "direction": direction,
                             "mode": str(rng.choice(["hover", "rise"] if event == "ledge" else ["hang", "rise"])),
                             "rise_speed": self.uniform(rng, r["rise_speed"]), "u_onset": float(rng.random())}
        if event == "ledge":
            ys = self.uniform(rng, r["shelf_y"])
            speed = self.uniform(rng, r["speed"])
            t_edge = self.uniform(rng, r["t_edge"])
            x_end = 5.0 + direction * self.uniform(rng, r["end_offset"])
            x0 = x_end - direction * speed * t_edge
            x_start = x0 - direction * (w / 2 + self.uniform(rng, [0.3, 0.8]))
            near = w / 2 + self.uniform(rng, r["screen_near"])
            far = w / 2 + self.uniform(rng, r["screen_far"])
            xs = sorted([x_end - direction * near, x_end + direction * far])
            p.update(shelf_y=ys, shelf_x=sorted([x_start, x_end]), x0=x0, y0=ys + BAR_R + h / 2,
                     vx=direction * speed, vy=0.0,
                     screen=[xs[0], FLOOR_Y - 0.3, xs[1], ys + BAR_R + h + self.uniform(rng, [0.4, 0.7])])
        else:
            p.update(x0=5.0 - direction * self.uniform(rng, r["throw_x"]),
                     y0=FLOOR_Y + h / 2 + self.uniform(rng, r["throw_height"]),
                     vx=direction * self.uniform(rng, r["throw_vx"]), vy=self.uniform(rng, r["throw_vy"]))
        return p

    def build(self, p: dict[str, Any], ctx: Context) -> Scene:
        look = p["look"]
        obj = Body(slot=ctx.slots[0], shape=look["shape"], width=look["width"], height=look["height"],
                   x=p["x0"], y=p["y0"], vx=p["vx"], vy=p["vy"], friction=0.0, elasticity=0.2,
                   intensity=look["intensity"])
        statics = [floor(friction=0.0, elasticity=0.3)]
        if p["event"] == "ledge":
            x0, x1 = p["shelf_x"]
            statics.append(Segment((x0, p["shelf_y"]), (x1, p["shelf_y"]), BAR_R, 0.0, 0.2, "shelf"))
        occ = [] if ctx.visible else [Occluder(*p["screen"])]
        return self.scene(ctx, [obj], statics, occ)

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        slot = ctx.slots[0]
        scene = self.build(p, ctx)
        possible = rollout(scene, ctx.cfg)
        truth = possible[1][:, slot]  # (T, F)
        h = p["look"]["height"]
        T = ctx.cfg.n_frames
        if p["event"] == "ledge":
            # last frame still on the shelf: before the centre drops or the object starts to tip
            rest_y = truth[0, 1]
            falling = (truth[:, 1] < rest_y - 0.02) | (np.abs(truth[:, 2]) > 0.02)
            at = int(np.argmax(falling)) - 1
            if not falling.any() or at < 3 or at > T - 8:
                raise ValueError(f"gravity: leaves the shelf at frame {at}; adjust t_edge in spec.yaml")
        else:
            # well above the floor, from just after the throw to a little past the apex
            high = np.flatnonzero(truth[:, 1] - h / 2 > FLOOR_Y + 0.9)
            apex = int(np.argmax(truth[:, 1]))
            at = pick(high, p["u_onset"], 4, min(apex + 4, T - 8), "mid-air stop")

        def float_away(world: World) -> None:
            world.set_gravity(slot, False)
            b = world.body(slot)
            vx = b.velocity.x if p["event"] == "ledge" else 0.0
            vy = p["rise_speed"] if p["mode"] == "rise" else 0.0
            world.set_velocity(slot, vx, vy, 0.0)

        return pair(scene, ctx.cfg, edited(at, float_away), f"{self.id} {p['event']}", possible)
