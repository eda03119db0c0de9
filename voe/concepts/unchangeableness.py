"""Unchangeableness: an object keeps its shape and size, seen or unseen.

Possible A: object X slides along the frictionless floor, behind a screen and out. Possible B:
object Y, which differs from X in shape, in width or in both, on the same x trajectory (same start
x, same velocity) and with the same height, so both rest at the same y. Impossible AB / BA splice A
and B from the onset ``t0`` on, so the object turns from X into Y (or back). Occluded variant:
``t0`` falls while both X and Y are fully behind the screen, so the object comes out changed.
Visible variant: ``t0`` falls while both are in plain view, so it morphs in sight.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import floor, hidden_frames, on_floor, pick, screen, splice_frames
from voe.sim.rollout import Recording, simulate

CHANGES = ("shape", "size", "both")
OTHER_SHAPE = {"circle": "box", "box": "circle"}


class Unchangeableness(Concept):
    name = "unchangeableness"
    version = 3
    kind = "quadruplet"
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        change = str(rng.choice(CHANGES))
        look_x = self.random_look(rng)
        h = look_x["height"]
        ratio = self.uniform(rng, r["size_ratio"])
        # v2: X and Y always have the same height, so both rest with their centre at the same y
        # and only shape or width can tell them apart (v1 let a size change show as a jump in y).
        if change == "shape":
            look_y = {**look_x, "shape": OTHER_SHAPE[look_x["shape"]]}
        elif change == "size":  # a box that gets wider or narrower
            look_x = {**look_x, "shape": "box"}
            look_y = {**look_x, "width": h * ratio}
        else:  # both: a ball of diameter h and a box h high, ratio * h wide
            look_x = {**look_x, "shape": "circle"}
            look_y = {**look_x, "shape": "box", "width": h * ratio}
        if rng.random() < 0.5:  # which of the two comes first
            look_x, look_y = look_y, look_x
        w_max = max(look_x["width"], look_y["width"])
        h_max = max(look_x["height"], look_y["height"])
        sx = self.uniform(rng, r["screen_x"])
        width = w_max + self.uniform(rng, r["screen_margin"])
        direction = 1 if rng.random() < 0.5 else -1
        # the bigger object touches the screen at frame t_in and has fully left it at frame t_out
        t_in = int(rng.integers(r["frame_in"][0], r["frame_in"][1] + 1))
        t_out = int(rng.integers(r["frame_out"][0], r["frame_out"][1] + 1))
        dt = ctx.cfg.dt
        speed = (width + w_max) / ((t_out - t_in) * dt)
        x0 = sx - direction * (width / 2 + w_max / 2 + speed * t_in * dt)
        return {"change": change, "look_x": look_x, "look_y": look_y, "screen_x": sx,
                "screen_width": width, "screen_height": h_max + 0.9, "speed": speed,
                "direction": direction, "x0": x0, "u_onset": float(rng.random())}

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        slot = ctx.slots[0]
        vx = p["direction"] * p["speed"]
        occ = screen(p["screen_x"], p["screen_width"], p["screen_height"], pad=ctx.pixel)
        a, b = (simulate(self.scene(ctx, [on_floor(p[look], slot, p["x0"], vx)], [floor()], [occ]),
                         ctx.cfg) for look in ("look_x", "look_y"))
        T = ctx.cfg.n_frames
        if ctx.visible:
            clear = _clear_of_screen(a, slot, occ) & _clear_of_screen(b, slot, occ)
            onset = pick(np.flatnonzero(clear), p["u_onset"], 3, T - 3, "morph in plain view")
        else:
            # both hidden (``present`` is pixel-accurate: no anti-aliased pixel shows)
            hidden = np.intersect1d(hidden_frames(a, slot), hidden_frames(b, slot))
            onset = pick(splice_frames(hidden), p["u_onset"], 2, T - 2, "morph behind the screen")
        return a, b, np.arange(T) >= onset


def _clear_of_screen(rec: Recording, slot: int, occ) -> np.ndarray:
    """``(T,)`` True where the object is present and its extent does not overlap the screen."""
    x, w = rec.states[:, slot, 0], rec.states[:, slot, 8]  # (T,), NaN when not present
    with np.errstate(invalid="ignore"):
        apart = (x + w / 2 < occ.x0) | (x - w / 2 > occ.x1)
        inside = (x - w / 2 >= 0) & (x + w / 2 <= rec.geometry["extent"][0])
    return rec.present[:, slot] & apart & inside
