"""Energy: a ball never bounces higher than it was dropped from.

Possible: a ball is dropped from rest at height ``h`` (its bottom above the floor) and bounces with
a restitution below one (ball elasticity times floor elasticity, pymunk multiplies them), so each
peak is lower than the last. Impossible: identical until the first impact, then on the impact frame
the rebound speed is raised so that the ball peaks at ``k * h`` with ``k > 1``. Occluded variant: a
low screen hides the impact, and the ball comes out of it going up too fast. Visible variant: the
impact is in plain view.

Pair, not splice: every possible clip of the scene peaks below its drop height after the impact,
and two possible clips that share the scene (drop from ``h1`` and from ``h2``) are never at the
same place with the same velocity, so a splice either teleports the ball or shows it dropped from
``h2`` rising to at most ``h2``, which is no violation of this concept.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.branch import edited, pair, rollout
from voe.concepts.parts import FLOOR_Y, floor, screen
from voe.sim.rollout import Recording
from voe.sim.scene import Body, Scene
from voe.sim.world import World

G = 9.81


class Energy(Concept):
    name = "energy"
    version = 1
    kind = "pair"

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        size = self.uniform(rng, r["size"])
        return {"main_slots": list(ctx.slots[:1]), "look": {"shape": "circle", "width": size, "height": size,
                         "intensity": self.uniform(rng, [0.65, 1.0])},
                "x": self.uniform(rng, r["x"]), "drop": self.uniform(rng, r["drop"]),
                "ball_elasticity": self.uniform(rng, r["ball_elasticity"]),
                "floor_elasticity": self.uniform(rng, r["floor_elasticity"]),
                "gain": self.uniform(rng, r["gain"]),
                "screen_width": size + self.uniform(rng, r["screen_margin"]),
                "screen_height": FLOOR_Y + size + self.uniform(rng, r["screen_above"]) - (FLOOR_Y - 0.3)}

    def build(self, p: dict[str, Any], ctx: Context) -> Scene:
        look = p["look"]
        ball = Body(slot=ctx.slots[0], shape="circle", width=look["width"], height=look["height"],
                    x=p["x"], y=FLOOR_Y + p["drop"] + look["height"] / 2, friction=0.0,
                    elasticity=p["ball_elasticity"], intensity=look["intensity"])
        occ = [] if ctx.visible else [screen(p["x"], p["screen_width"], p["screen_height"])]
        return self.scene(ctx, [ball], [floor(friction=0.0, elasticity=p["floor_elasticity"])], occ)

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        slot = ctx.slots[0]
        scene = self.build(p, ctx)
        possible = rollout(scene, ctx.cfg)
        vy = possible[1][:, slot, 4]  # (T,)
        rising = np.flatnonzero(vy > 0)
        if rising.size == 0 or rising[0] > ctx.cfg.n_frames - 10:
            raise ValueError(f"energy: first impact at frame {rising[:1]}; lower `drop` in spec.yaml")
        impact = int(rising[0])  # first frame after the floor has sent the ball back up
        r = p["look"]["height"] / 2
        peak_y = FLOOR_Y + r + p["gain"] * p["drop"]  # centre height of the impossible peak

        def boost(world: World) -> None:
            y = world.body(slot).position.y
            world.set_velocity(slot, 0.0, float(np.sqrt(2 * G * (peak_y - y))), 0.0)

        return pair(scene, ctx.cfg, edited(impact, boost), self.id, possible)
