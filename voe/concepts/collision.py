"""Collision: objects do not pass through each other and do not act at a distance.

Two objects that look clearly different (one dim, one bright; a narrow and a wide box, or a ball
and a box) slide on a frictionless floor towards each other. They have the same height, so every
hit is head-on: v1's objects of different heights met off-centre, the hit object tipped and rocked
on the floor, and a physics observer restarting from each frame could not follow the rocking,
which made the possible collision nearly as surprising as an impossible one. Possible: they collide and exchange momentum. Impossible,
pass-through: from the last frame before contact object 1 ignores object 2 and slides on through
it, object 2 carrying on as if nothing had touched it. Impossible, action at a distance (visible
sets only): while a clear gap still separates them, object 1 stops dead and object 2 sets off with
the velocity the collision would have given it. Occluded variant: object 2 moves slowly towards
object 1 and the contact happens behind a screen covering both, so the pass-through shows as the
two objects coming out on the wrong sides (their order reversed). Visible variant: object 2 rests
in plain view until it is hit.

Pair, not splice: every possible clip in the same scene keeps the two objects in their order
along the floor and starts object 2 moving only on contact; a splice of two possible clips only
teleports objects, so it cannot show one object sliding through another or moving another from
afar.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.branch import edited, first_difference, pair, rollout
from voe.concepts.parts import FLOOR_Y, floor, on_floor, pick, screen
from voe.sim.rollout import Recording
from voe.sim.scene import Scene
from voe.sim.world import World


class Collision(Concept):
    name = "collision"
    version = 2
    kind = "pair"
    confounded = True  # a branch pair: impossible frames are new (see probes/README)
    n_main = 2

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        sizes = [self.uniform(rng, r["small"]), self.uniform(rng, r["large"])]
        shades = [self.uniform(rng, r["dim"]), self.uniform(rng, r["bright"])]
        if rng.random() < 0.5:
            sizes.reverse()
        if rng.random() < 0.5:
            shades.reverse()
        # one height for both, so that every hit is head-on (through both centres): no torque, no
        # tipping, a clean exchange of momentum; a box's width is its own, a ball's is the height
        height = self.uniform(rng, r["height"])
        shapes = [str(rng.choice(["circle", "box"])) for _ in range(2)]
        sizes = [height if sh == "circle" else s for sh, s in zip(shapes, sizes, strict=True)]
        looks = [{"shape": sh, "width": s, "height": height, "intensity": i}
                 for sh, s, i in zip(shapes, sizes, shades, strict=True)]
        direction = 1 if rng.random() < 0.5 else -1
        v1 = self.uniform(rng, r["speed"])
        v2 = 0.0 if ctx.visible else self.uniform(rng, r["approach"])
        t_c = self.uniform(rng, r["t_contact"])
        xc = self.uniform(rng, r["contact_x"])
        w1, w2 = sizes
        m = self.uniform(rng, r["screen_margin"])
        xs = sorted([xc - direction * (w1 + m), xc + direction * (w2 + m)])
        return {"main_slots": list(ctx.slots[:2]), "looks": looks, "direction": direction, "v1": v1, "v2": v2,
                "x1": xc - direction * (w1 / 2 + v1 * t_c), "x2": xc + direction * (w2 / 2 + v2 * t_c),
                "elasticity": [self.uniform(rng, r["elasticity"]) for _ in range(2)],
                "mode": "pass" if not ctx.visible or rng.random() < 0.5 else "distance",
                "u_onset": float(rng.random()),
                "screen": [xs[0], xs[1], FLOOR_Y + height + self.uniform(rng, [0.5, 0.8])]}

    def build(self, p: dict[str, Any], ctx: Context) -> Scene:
        d = p["direction"]
        bodies = [on_floor(look, ctx.slots[i], x, v, elasticity=e, mass=look["width"] * look["height"])
                  for i, (look, x, v, e) in enumerate(zip(p["looks"], [p["x1"], p["x2"]],
                                                          [d * p["v1"], -d * p["v2"]], p["elasticity"],
                                                          strict=True))]
        x0, x1, top = p["screen"]
        occ = [] if ctx.visible else [screen((x0 + x1) / 2, x1 - x0, top - (FLOOR_Y - 0.3))]
        return self.scene(ctx, bodies, [floor(friction=0.0, elasticity=0.5)], occ)

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        s1, s2 = ctx.slots[0], ctx.slots[1]
        scene = self.build(p, ctx)
        possible = rollout(scene, ctx.cfg)
        truth = possible[1]  # (T, K, F)
        _, ghost = rollout(scene, ctx.cfg, edited(0, lambda w: w.set_passable(s1, False, True)))
        contact = first_difference(truth[:, [s1, s2], :6], ghost[:, [s1, s2], :6])
        T = ctx.cfg.n_frames
        if contact < 4 or contact > T - 8:
            raise ValueError(f"collision: contact at frame {contact}; adjust t_contact in spec.yaml")
        if p["mode"] == "pass":
            hook = edited(contact - 1, lambda w: w.set_passable(s1, statics=False, objects=True))
        else:
            w1, w2 = p["looks"][0]["width"], p["looks"][1]["width"]
            gap = np.abs(truth[:, s2, 0] - truth[:, s1, 0]) - (w1 + w2) / 2  # (T,)
            lo, hi = self.ranges["gap"]
            frames = np.flatnonzero((gap > lo) & (gap < hi))
            at = pick(frames, p["u_onset"], 3, contact - 1, "action at a distance")
            kick = truth[min(contact + 3, T - 1), s2, 3:5]  # object 2's velocity after the real hit

            def at_a_distance(world: World) -> None:
                world.set_velocity(s1, 0.0, 0.0)
                world.set_velocity(s2, float(kick[0]), float(kick[1]))

            hook = edited(at, at_a_distance)
        return pair(scene, ctx.cfg, hook, f"{self.id} {p['mode']}", possible)
