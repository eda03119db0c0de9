"""Permanence: objects do not vanish or appear from nowhere.

Possible A: an object slides across the floor, behind a screen and out again. Possible B: the
same scene without the object. Impossible AB / BA splice A and B from the onset on, so the
object vanishes (AB) or appears from nowhere (BA). Occluded variant: the onset falls while the
object is behind the screen, so AB's object never comes out and BA's comes out of an empty
screen. Visible variant: the onset falls while the object is in plain view.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import floor, hidden_frames, on_floor, pick, screen, splice_frames, visible_frames
from voe.sim.rollout import Recording, simulate


class Permanence(Concept):
    name = "permanence"
    version = 2
    kind = "quadruplet"
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        sx = self.uniform(rng, r["screen_x"])
        width = look["width"] + self.uniform(rng, r["screen_margin"])
        speed = self.uniform(rng, r["speed"])
        direction = 1 if rng.random() < 0.5 else -1
        # start so that the object reaches the screen's near edge after 0.1..0.2 of the clip,
        # leaving time to come out on the far side before the end
        t_reach = self.uniform(rng, [0.1, 0.2]) * ctx.cfg.n_frames * ctx.cfg.dt
        x0 = sx - direction * (width / 2 + look["width"] / 2 + speed * t_reach)
        return {"look": look, "screen_x": sx, "screen_width": width,
                "screen_height": look["height"] + 0.9, "speed": speed, "direction": direction,
                "x0": x0, "u_onset": float(rng.random())}

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        slot = ctx.slots[0]
        obj = on_floor(p["look"], slot, p["x0"], p["direction"] * p["speed"])
        occ = [screen(p["screen_x"], p["screen_width"], p["screen_height"], pad=ctx.pixel)]
        a = simulate(self.scene(ctx, [obj], [floor()], occ), ctx.cfg)
        b = simulate(self.scene(ctx, [], [floor()], occ), ctx.cfg)
        T = ctx.cfg.n_frames
        if ctx.visible:
            onset = pick(visible_frames(a, slot), p["u_onset"], 4, T - 4, "visible vanishing")
        else:
            hid = hidden_frames(a, slot)
            if hid.size:  # the first hidden stretch is the passage behind the screen
                hid = hid[: int(np.argmax(np.diff(np.append(hid, -9)) != 1)) + 1]
            seen = visible_frames(a, slot)
            if hid.size == 0 or (seen > hid[-1]).sum() < 3:
                raise ValueError("the object does not come out of the screen for 3 frames")
            onset = pick(splice_frames(hid), p["u_onset"], 2, T - 2, "occluded vanishing")
        mask = np.arange(T) >= onset
        return a, b, mask
