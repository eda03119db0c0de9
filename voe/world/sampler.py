"""Sample one ordinary-physics training scene on the same stage as the probes.

Why: a learned simulator must see every kind of motion the probes test (sliding, dropping,
throwing, bouncing, object collisions, shelves, ramps, objects passing behind screens, the
distractor lane) *without* violations, so its surprise at a probe can only come from the
violation. Scenes reuse the probes' floor, screens and lane (``voe.concepts.parts`` and the lane of
``voe.concepts.base``), so nothing about the stage itself is new to a model at test time.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept
from voe.concepts.parts import FLOOR_Y, floor, screen
from voe.sim.scene import Body, Occluder, Scene, Segment, SimConfig
from voe.world.hidden import CEILING, hidden_event  # main events stay below the distractor lane

#: Probability of each motion a main object starts with.
MOTIONS = {"slide": 0.3, "drop": 0.2, "throw": 0.2, "shelf": 0.1, "ramp": 0.1, "rest": 0.1}
#: Probability, when hidden events are asked for, that a scene's first main object(s) take part
#: in an event behind a screen (``voe.world.hidden``): free flight, a bounce off a wall, a collision.
#: Off by default: measured on dev seeds 4077 and 5309 it did not help ``interaction-v3`` (docs/models-findings.md).
HIDDEN_P = 0.4


def _look(rng: np.random.Generator) -> dict[str, Any]:
    size = float(rng.uniform(0.5, 1.3))
    return {"shape": str(rng.choice(["circle", "box"])), "width": size, "height": size,
            "intensity": float(rng.uniform(0.6, 1.0))}


def _bbox(b: Body) -> tuple[float, float, float, float]:
    r = 0.75 * max(b.width, b.height)  # covers a rotated box
    return b.x - r, b.y - r, b.x + r, b.y + r


def _overlaps(b: Body, others: list[Body]) -> bool:
    x0, y0, x1, y1 = _bbox(b)
    return any(x0 < o1 and o0 < x1 and y0 < p1 and p0 < y1
               for o0, p0, o1, p1 in (_bbox(o) for o in others))


def _statics(rng: np.random.Generator) -> tuple[list[Segment], dict[str, Any]]:
    """Floor plus, sometimes, a shelf, a ramp and a wall."""
    segs = [floor(friction=float(rng.choice([0.0, 0.0, 0.4])), elasticity=float(rng.uniform(0.3, 0.9)))]
    info: dict[str, Any] = {}
    if rng.random() < 0.35:
        y = float(rng.uniform(2.5, 5.0))
        x0 = float(rng.uniform(0.0, 5.0))
        x1 = x0 + float(rng.uniform(2.0, 4.0))
        segs.append(Segment((x0, y), (x1, y), 0.1, 0.0, 0.5, "shelf"))
        info["shelf"] = (x0, x1, y)
    if rng.random() < 0.3:
        side = 1 if rng.random() < 0.5 else -1
        foot = float(rng.uniform(3.0, 7.0))
        top = foot - side * float(rng.uniform(2.0, 3.5))
        h = float(rng.uniform(1.0, 2.5))
        segs.append(Segment((foot, FLOOR_Y - 0.1), (top, FLOOR_Y - 0.1 + h), 0.1, 0.5, 0.3, "ramp"))
        info["ramp"] = (foot, top, FLOOR_Y - 0.1 + h)
    if rng.random() < 0.2:
        x = 0.3 if rng.random() < 0.5 else 9.7
        segs.append(Segment((x, FLOOR_Y), (x, FLOOR_Y + float(rng.uniform(1.5, 4.0))), 0.1, 0.0, 0.8, "wall"))
    return segs, info


def _occluders(rng: np.random.Generator) -> list[Occluder]:
    n = int(rng.choice([0, 1, 2], p=[0.25, 0.5, 0.25]))
    out = []
    for _ in range(n):
        w, h = float(rng.uniform(1.2, 3.0)), float(rng.uniform(1.5, 3.5))
        cx = float(rng.uniform(1.5, 8.5))
        if rng.random() < 0.75:
            out.append(screen(cx, w, h))
        else:  # a raised screen: falling and thrown objects pass behind it
            bottom = float(rng.uniform(1.5, 4.0))
            out.append(Occluder(cx - w / 2, bottom, cx + w / 2, bottom + h))
    return out


def _body(rng: np.random.Generator, slot: int, motion: str, info: dict[str, Any]) -> Body:
    look = _look(rng)
    half = look["height"] / 2
    kw = dict(slot=slot, shape=look["shape"], width=look["width"], height=look["height"],
              intensity=look["intensity"], elasticity=float(rng.uniform(0.1, 0.9)),
              friction=float(rng.choice([0.0, 0.0, 0.5])), mass=look["width"] * look["height"])
    if motion == "shelf" and "shelf" in info:
        x0, x1, y = info["shelf"]
        return Body(x=float(rng.uniform(x0, x1)), y=y + 0.1 + half, vx=float(rng.uniform(-2.5, 2.5)), **kw)
    if motion == "ramp" and "ramp" in info:
        foot, top, y = info["ramp"]
        return Body(x=top + np.sign(foot - top) * 0.6, y=y + 0.6 + half, **kw)
    if motion in ("drop", "shelf", "ramp"):
        return Body(x=float(rng.uniform(1.0, 9.0)), y=float(rng.uniform(2.5, CEILING - half)),
                    vx=float(rng.uniform(-1.0, 1.0)), **kw)
    if motion == "throw":
        side = 1 if rng.random() < 0.5 else -1
        x = float(rng.uniform(0.5, 3.0)) if side > 0 else float(rng.uniform(7.0, 9.5))
        return Body(x=x, y=float(rng.uniform(1.5, 4.0)), vx=side * float(rng.uniform(1.5, 5.0)),
                    vy=float(rng.uniform(0.0, 5.0)), omega=float(rng.uniform(-3, 3)), **kw)
    vx = 0.0 if motion == "rest" else float(rng.uniform(-4.0, 4.0))
    return Body(x=float(rng.uniform(-0.5, 10.5)), y=FLOOR_Y + half, vx=vx, **kw)


def sample_scene(rng: np.random.Generator, cfg: SimConfig, hidden_p: float = 0.0) -> tuple[Scene, dict[str, Any]]:
    """One training scene and a JSON-able summary of how it was drawn.

    ``hidden_p`` > 0: that share of scenes puts its main event behind a screen (``voe.world.hidden``);
    at 0 no extra random number is drawn, so the default world is the one before the option existed.
    """
    n_distractors = int(rng.choice([0, 1, 2], p=[0.5, 0.3, 0.2]))
    slots = [int(s) for s in rng.permutation(cfg.n_slots)]
    n_main = int(rng.integers(1, cfg.n_slots - n_distractors + 1))
    statics, info = _statics(rng)
    occluders = _occluders(rng)
    bodies: list[Body] = []
    motions: list[str] = []
    if hidden_p > 0 and rng.random() < hidden_p:
        kind, bodies, segs, occ = hidden_event(rng, [_look(rng) for _ in range(2)], slots[:n_main])
        if len(bodies) == 2 and _overlaps(bodies[1], bodies[:1]):
            bodies = bodies[:1]  # a drawn collision whose bodies would start overlapping
        motions = [f"hidden-{kind}"] * len(bodies)
        statics, occluders = statics + segs, occluders[:1] + occ
    collide = n_main >= 2 and rng.random() < 0.5
    resting_target = rng.random() < 0.5  # the probes' collisions hit an object at rest
    for i in range(len(bodies), n_main):
        motion = str(rng.choice(list(MOTIONS), p=list(MOTIONS.values())))
        for _ in range(20):
            b = _body(rng, slots[i], motion, info)
            if collide and i < 2:  # two objects on the floor, sliding towards each other or one at rest
                x = float(rng.uniform(0.5, 4.0)) if i == 0 else float(rng.uniform(6.0, 9.5))
                b = b.moved(x=x, y=FLOOR_Y + b.height / 2, vy=0.0, omega=0.0,
                            vx=0.0 if (i == 1 and resting_target) else
                            (1 if i == 0 else -1) * float(rng.uniform(1.0, 4.0)))
                motion = "collide"
            if not _overlaps(b, bodies):
                break
        else:
            continue  # no room: leave the slot empty
        bodies.append(b)
        motions.append(motion)
    distractors = Concept._distractors(rng, n_distractors, tuple(slots[n_main:]))
    scene = Scene(bodies=tuple(bodies) + distractors,
                  statics=tuple(statics) + Concept._lane(n_distractors), occluders=tuple(occluders))
    return scene, {"motions": motions, "n_main": len(bodies), "n_distractors": n_distractors,
                   "collide": bool(collide)}
