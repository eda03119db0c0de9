"""Continuity: an object travels along a connected path; it does not teleport between occluders.

Possible A: an object slides across the floor behind screen 1, through a visible gap, behind
screen 2 and out. Possible B: the same two screens without the object. The splice mask is a middle
interval ``[t1, t2)``: AB shows the object go behind screen 1, never cross the gap, and come out of
screen 2; BA shows it appear in the gap from nowhere and vanish again. Occluded variant: ``t1``
falls while the object is hidden behind screen 1 and ``t2`` while it is hidden behind screen 2, so
the gap crossing itself is what is missing. Visible variant: ``t1`` and ``t2`` both fall while the
object is fully in view in the gap, so it vanishes there and reappears further along.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.parts import floor, hidden_frames, on_floor, pick, screen, splice_frames
from voe.sim.rollout import Recording, simulate


class Continuity(Concept):
    name = "continuity"
    version = 2
    kind = "quadruplet"
    conditions = ("perceptual", "occluded")
    balance = {"occluded": "F+M+T2+P+V+H+D", "perceptual": "F+P+V+H"}

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        r = self.ranges
        look = self.random_look(rng)
        s = look["width"]
        screen_w = s + self.uniform(rng, r["screen_margin"])
        gap = s + self.uniform(rng, r["gap_margin"])  # clear floor between the two screens
        centre = self.uniform(rng, r["centre_x"])
        direction = 1 if rng.random() < 0.5 else -1
        span = 2 * screen_w + gap
        # screen 1 is the one the object meets first
        sx1 = centre - direction * (gap + screen_w) / 2
        sx2 = centre + direction * (gap + screen_w) / 2
        # the object touches screen 1 at frame t_in and has fully left screen 2 at frame t_out
        t_in = int(rng.integers(r["frame_in"][0], r["frame_in"][1] + 1))
        t_out = int(rng.integers(r["frame_out"][0], r["frame_out"][1] + 1))
        dt = ctx.cfg.dt
        speed = (s + span) / ((t_out - t_in) * dt)
        x0 = centre - direction * (span / 2 + s / 2 + speed * t_in * dt)
        return {"look": look, "screen_x": [sx1, sx2], "screen_width": screen_w,
                "screen_height": look["height"] + 0.9, "gap": gap, "speed": speed,
                "direction": direction, "x0": x0,
                "u_t1": float(rng.random()), "u_t2": float(rng.random())}

    def _possible_pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        slot = ctx.slots[0]
        obj = on_floor(p["look"], slot, p["x0"], p["direction"] * p["speed"])
        occ = [screen(x, p["screen_width"], p["screen_height"], pad=ctx.pixel) for x in p["screen_x"]]
        a = simulate(self.scene(ctx, [obj], [floor()], occ), ctx.cfg)
        b = simulate(self.scene(ctx, [], [floor()], occ), ctx.cfg)
        T = ctx.cfg.n_frames
        if ctx.visible:
            full = in_gap_frames(a, slot, p)
            t1 = pick(full[:-2], p["u_t1"], 1, T - 1, "vanishing in the gap")
            t2 = pick(full, p["u_t2"], t1 + 2, T, "reappearing in the gap")
        else:
            hid = hidden_frames(a, slot)  # pixel-accurate: no anti-aliased pixel shows
            x = p["x0"] + p["direction"] * p["speed"] * hid * ctx.cfg.dt  # true x while hidden
            behind = [hid[np.abs(x - sx) <= p["screen_width"] / 2] for sx in p["screen_x"]]
            t1 = pick(splice_frames(behind[0]), p["u_t1"], 1, T - 1, "hidden behind screen 1")
            t2 = pick(splice_frames(behind[1]), p["u_t2"], t1 + 1, T, "hidden behind screen 2")
        t = np.arange(T)
        return a, b, (t >= t1) & (t < t2)


def in_gap_frames(rec: Recording, slot: int, p: dict[str, Any]) -> np.ndarray:
    """Frames where the object is entirely in view inside the gap between the screens."""
    x = rec.states[:, slot, 0]  # (T,), NaN when not present
    half = p["look"]["width"] / 2
    lo = min(p["screen_x"]) + p["screen_width"] / 2 + half
    hi = max(p["screen_x"]) - p["screen_width"] / 2 - half
    with np.errstate(invalid="ignore"):
        ok = rec.present[:, slot] & (x >= lo) & (x <= hi)
    return np.flatnonzero(ok)
