"""Training scenes whose main event happens behind a screen: free flight, a bounce off a wall,
a collision.

Why (measured, docs/models-findings.md "Why the trained v3 does not learn gravity, solidity and collision", dev
seed 4077): in the ordinary training world only 2.3 % of visible object-frames are rising and a
hidden stretch occurs about 0.3 times per clip, so a learned rollout never sees an object turn
round, hit a wall or another object while it is hidden. The trained network then carries a hidden
ball thrown up without gravity and its variance blows up within 3 hidden frames, so early, on-time
and late reappearances cost the same. These scenes are ordinary physics (no violation, no probe
parameters): the same stage (floor, screens, walls) with the event placed where a screen covers
part of it, so hidden rollouts are scored at every reappearance with the right law. Where the
screen sits relative to the event is drawn broadly (it may hide the rise, the apex, the fall, the
contact or nothing), so no hiding pattern of a probe is copied.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.parts import FLOOR_Y, G, screen
from voe.sim.scene import Body, Occluder, Segment

CEILING = 7.0  # main events and screens stay below the distractor lane (``sampler`` uses it too)

#: Probability of each hidden event, given that a scene has one.
HIDDEN_EVENTS = {"toss": 0.4, "wall": 0.3, "collide": 0.3}


def _on_floor(look: dict[str, Any], slot: int, x: float, vx: float, rng: np.random.Generator) -> Body:
    return Body(slot=slot, shape=look["shape"], width=look["width"], height=look["height"],
                intensity=look["intensity"], x=x, y=FLOOR_Y + look["height"] / 2, vx=vx,
                elasticity=float(rng.uniform(0.1, 0.9)), friction=0.0,
                mass=look["width"] * look["height"])


def toss(rng: np.random.Generator, look: dict[str, Any], slot: int
         ) -> tuple[list[Body], list[Segment], list[Occluder]]:
    """A body thrown up from the floor (nearly vertically) with a raised screen across part of
    its flight: the screen's bottom and height are drawn over the whole flight, so it hides the
    rise, the apex, the fall or all of them."""
    h = look["height"]
    apex = FLOOR_Y + float(rng.uniform(1.5, 5.0))  # the body's bottom at the apex
    vy = float(np.sqrt(2 * G * (apex - FLOOR_Y)))
    x = float(rng.uniform(1.5, 8.5))
    ball = Body(slot=slot, shape=look["shape"], width=look["width"], height=h, intensity=look["intensity"],
                x=x, y=FLOOR_Y + h / 2, vx=float(rng.uniform(-0.8, 0.8)), vy=vy,
                omega=float(rng.uniform(-1, 1)), elasticity=float(rng.uniform(0.1, 0.7)),
                friction=float(rng.choice([0.0, 0.5])), mass=look["width"] * h)
    bottom = FLOOR_Y + float(rng.uniform(0.3, max(0.4, apex - FLOOR_Y)))
    top = min(bottom + float(rng.uniform(1.5, 4.0)), CEILING)
    half = (look["width"] + float(rng.uniform(0.4, 2.0))) / 2
    cx = x + float(rng.uniform(-0.4, 0.4))
    return [ball], [], [Occluder(cx - half, bottom, cx + half, top)]


def wall(rng: np.random.Generator, look: dict[str, Any], slot: int
         ) -> tuple[list[Body], list[Segment], list[Occluder]]:
    """A body sliding into a wall inside the window, a floor screen covering the wall and some
    floor before it (sometimes the bounce comes back into view, sometimes not)."""
    side = 1 if rng.random() < 0.5 else -1  # the wall is on this side of the window
    wall_x = 5.0 + side * float(rng.uniform(1.0, 4.2))
    height = look["height"] + float(rng.uniform(0.4, 1.6))  # the screen
    sw = float(rng.uniform(1.5, 3.5))
    cx = wall_x - side * float(rng.uniform(0.0, sw / 2))
    top = FLOOR_Y + height + float(rng.uniform(0.0, 1.5))
    seg = Segment((wall_x, FLOOR_Y), (wall_x, top), 0.1, 0.0, float(rng.uniform(0.6, 1.0)), "wall")
    speed = float(rng.uniform(1.5, 5.0))
    x0 = wall_x - side * float(rng.uniform(2.5, 6.0))
    x0 = float(np.clip(x0, -0.5, 10.5))
    body = _on_floor(look, slot, x0, side * speed, rng)
    return [body], [seg], [screen(cx, sw, height)]


def collide(rng: np.random.Generator, looks: list[dict[str, Any]], slots: list[int]
            ) -> tuple[list[Body], list[Segment], list[Occluder]]:
    """Two bodies on the floor, one moving into the other (at rest or moving towards it), the
    contact point behind a floor screen that may or may not hide the bodies' runs after it."""
    speed = float(rng.uniform(1.0, 4.0))
    contact = float(rng.uniform(3.0, 7.0))
    t_c = float(rng.uniform(0.5, 1.3))  # seconds to contact
    target_moves = rng.random() < 0.5
    v2 = -float(rng.uniform(0.5, 2.0)) if target_moves else 0.0
    a = _on_floor(looks[0], slots[0], contact - speed * t_c - looks[0]["width"] / 2, speed, rng)
    b = _on_floor(looks[1], slots[1], contact - v2 * t_c + looks[1]["width"] / 2, v2, rng)
    height = max(looks[0]["height"], looks[1]["height"]) + float(rng.uniform(0.3, 1.5))
    sw = float(rng.uniform(1.5, 4.0))
    cx = contact + float(rng.uniform(-0.5, 0.5))
    bodies, occ = [a, b], [screen(cx, sw, height)]
    if rng.random() < 0.5:  # mirrored: the mover comes from the right
        bodies = [q.moved(x=10.0 - q.x, vx=-q.vx) for q in bodies]
        occ = [Occluder(10.0 - o.x1, o.y0, 10.0 - o.x0, o.y1) for o in occ]
    return bodies, [], occ


def hidden_event(rng: np.random.Generator, looks: list[dict[str, Any]], slots: list[int]
                 ) -> tuple[str, list[Body], list[Segment], list[Occluder]]:
    """One hidden event (``HIDDEN_EVENTS``) using the first one or two of ``looks`` and ``slots``."""
    kind = str(rng.choice(list(HIDDEN_EVENTS), p=list(HIDDEN_EVENTS.values())))
    if kind == "collide" and len(slots) < 2:
        kind = "toss"
    if kind == "collide":
        return (kind, *collide(rng, looks[:2], slots[:2]))
    return (kind, *(toss if kind == "toss" else wall)(rng, looks[0], slots[0]))
