"""Energy: a ball never bounces higher than the top of its flight.

Possible: a ball is tossed up (and sideways) so that the top of its flight is ``h`` above the
floor (its bottom); it falls and bounces with a restitution below one (ball elasticity times floor
elasticity, pymunk multiplies them), so it peaks lower than ``h``. Impossible: identical until the
impact, which has restitution ``sqrt(k)`` with ``k > 1`` (the ball's elasticity is raised just
before it lands), so the ball rises towards ``k * h``. Occluded variant: a narrow pillar, as tall
as the window, hides the impact; the ball comes out of it going up too fast. Both clips' balls
have the same horizontal motion, so they are hidden on exactly the same frames. Visible variant:
the same drift, no pillar.

Why the toss and the timing: the bounce comes late (frame 24-28), so that both clips hold exactly
one; with an early drop (v1) the lower-bouncing possible ball bounced again within the clip and
the impossible one did not, and a model unsure about bounces paid for the extra one. The energy
comes from the bounce itself, not from a kick in mid-air (v1 raised the velocity one frame after
the bounce): a kick is also a break of inertia, and a model that allows bounces to gain energy
must find the impossible clip ordinary.

Pair, not splice: every possible clip of the scene peaks below the top of its toss after the impact,
and two possible clips that share the scene (drop from ``h1`` and from ``h2``) are never at the
same place with the same velocity, so a splice either teleports the ball or shows it dropped from
``h2`` rising to at most ``h2``, which is no violation of this concept.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.branch import edited, pair, rollout
from voe.concepts.parts import FLOOR_Y, PILLAR, G, floor, screen
from voe.sim.rollout import Recording
from voe.sim.scene import Body, Scene
from voe.sim.world import World


class Energy(Concept):
    name = "energy"
    version = 2
    kind = "pair"
    confounded = True  # a branch pair: impossible frames are new (see probes/README)

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        size = self.uniform(rng, r["size"])
        x = self.uniform(rng, r["x"])
        return {"main_slots": list(ctx.slots[:1]), "look": {"shape": "circle", "width": size, "height": size,
                         "intensity": self.uniform(rng, [0.65, 1.0])},
                "x": x, "drop": self.uniform(rng, r["drop"]), "t_up": self.uniform(rng, r["t_up"]),
                "ball_elasticity": self.uniform(rng, r["ball_elasticity"]),
                "floor_elasticity": self.uniform(rng, r["floor_elasticity"]),
                "gain": self.uniform(rng, r["gain"]),
                "vx": float(np.sign(5.0 - x)) * self.uniform(rng, r["drift"]),  # towards the centre
                "screen_width": size + self.uniform(rng, r["screen_margin"])}

    def build(self, p: dict[str, Any], ctx: Context) -> Scene:
        look = p["look"]
        vy0 = G * p["t_up"]  # tossed up so that the top of its flight is `drop` above the floor
        ball = Body(slot=ctx.slots[0], shape="circle", width=look["width"], height=look["height"],
                    x=p["x"], y=FLOOR_Y + p["drop"] - vy0 ** 2 / (2 * G) + look["height"] / 2,
                    vx=p["vx"], vy=vy0, friction=0.0, elasticity=p["ball_elasticity"],
                    intensity=look["intensity"])
        # a pillar as tall as the window, centred where the ball lands: the ball is hidden exactly
        # while it passes behind it, whatever its height, so both clips show it equally long
        x_land = p["x"] + p["vx"] * (p["t_up"] + float(np.sqrt(2 * p["drop"] / G)))
        occ = [] if ctx.visible else [screen(x_land, p["screen_width"], PILLAR, pad=ctx.pixel)]
        return self.scene(ctx, [ball], [floor(friction=0.0, elasticity=p["floor_elasticity"])], occ)

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        slot = ctx.slots[0]
        scene = self.build(p, ctx)
        possible = rollout(scene, ctx.cfg)
        vy = possible[1][:, slot, 4]  # (T,)
        falling = int(np.argmax(vy < 0))
        rising = np.flatnonzero(vy[falling:] > 0) + falling
        if rising.size == 0 or rising[0] > ctx.cfg.n_frames - 10:
            raise ValueError(f"energy: first impact at frame {rising[:1]}; adjust `drop`/`t_up` in spec.yaml")
        impact = int(rising[0])  # first frame after the floor has sent the ball back up
        elasticity = float(np.sqrt(p["gain"]) / p["floor_elasticity"])  # restitution sqrt(gain) > 1

        def springy(world: World) -> None:
            world.set_elasticity(slot, elasticity)

        return pair(scene, ctx.cfg, edited(impact - 1, springy), self.id, possible)
