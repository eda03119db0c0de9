"""Gravity: objects in flight fall; they do not float on.

An object is thrown in an arc. Possible: it falls back and lands on the floor. Impossible: near
the top of its arc its gravity is switched off, and it flies on in a straight line at the velocity
it had, nearly level. Occluded variant: a narrow pillar, taller than the window, stands where the
object reaches the top of its arc, so gravity goes off behind it and the object comes out of the
far side too high. Visible variant: no pillar.

Only gravity is broken: the object's velocity is never touched, so no break of inertia comes with
the float (v1's objects also stopped dead in mid-air or were kicked upwards). The floor is
frictionless, so the object's horizontal motion is the same in both clips and it is in view on
the same frames. The object is in free flight at the onset, so nothing but gravity decides the
outcome: v1's ledge event (an object sliding off a shelf) also needed support by the shelf, which
a model without collisions does not have.

Pair, not splice: the impossible path (level flight after the top of an arc) is not a piece of any
possible clip in the same scene, so no splice of two possible clips shows it; a splice would only
make the object jump between two falling paths.
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


class Gravity(Concept):
    name = "gravity"
    version = 2
    kind = "pair"
    confounded = True  # a branch pair: impossible frames are new (see probes/README)

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        direction = 1 if rng.random() < 0.5 else -1
        vx, vy = direction * self.uniform(rng, r["throw_vx"]), self.uniform(rng, r["throw_vy"])
        x0 = 5.0 - direction * self.uniform(rng, r["throw_x"])
        lo, hi = r["apex_window"]
        apex = int(round(vy / G / ctx.cfg.dt))  # frame of the top of the arc
        onset_at = apex + int(rng.integers(lo, hi + 1))  # the last frame with gravity on
        return {"main_slots": list(ctx.slots[:1]), "look": look, "direction": direction,
                "x0": x0, "y0": FLOOR_Y + look["height"] / 2 + self.uniform(rng, r["throw_height"]),
                "vx": vx, "vy": vy, "at": onset_at,
                # the pillar is centred where the object is when gravity goes off
                "pillar": [x0 + vx * onset_at * ctx.cfg.dt, look["width"] + self.uniform(rng, r["pillar_margin"])]}

    def build(self, p: dict[str, Any], ctx: Context) -> Scene:
        look = p["look"]
        obj = Body(slot=ctx.slots[0], shape=look["shape"], width=look["width"], height=look["height"],
                   x=p["x0"], y=p["y0"], vx=p["vx"], vy=p["vy"], friction=0.0, elasticity=0.2,
                   intensity=look["intensity"])
        cx, width = p["pillar"]
        occ = [] if ctx.visible else [screen(cx, width, PILLAR, pad=ctx.pixel)]
        return self.scene(ctx, [obj], [floor(friction=0.0, elasticity=0.3)], occ)

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        slot = ctx.slots[0]
        scene = self.build(p, ctx)
        at = p["at"]
        if not 3 <= at <= ctx.cfg.n_frames - 8:
            raise ValueError(f"gravity: gravity goes off at frame {at}; adjust throw_vy in spec.yaml")

        def float_on(world: World) -> None:
            world.set_gravity(slot, False)  # velocity untouched: only gravity is broken

        return pair(scene, ctx.cfg, edited(at, float_on), self.id, rollout(scene, ctx.cfg))
