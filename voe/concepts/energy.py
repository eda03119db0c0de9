"""Energy: a ball that bounces off a wall never comes back faster than it went in.

Possible (v6): a ball slides on a frictionless floor, without rolling, at ``u`` towards a wall; it
bounces once with a restitution ``e`` below one (ball elasticity times wall elasticity, pymunk
multiplies them) and slides back at ``e u``. Impossible: the same clip played backwards (time
reversal): the ball comes in at ``e u`` and leaves at ``u``, gaining energy from nowhere at the
bounce. No restitution a static wall can have does that, so no impossible clip is possible under
other parameters. The frames are exactly those of the possible clip and so are the per-step
changes, positions, speeds and heights (F+M+P+V+H+D); with the left-right mirrors of both clips
(``kind = "mirrored"``, ``voe.concepts.mirror``) every signed horizontal step and velocity occurs on
both sides (``X``); and nothing moves vertically (the ball rests on the floor, the distractors on
their lane), so every signed vertical step and velocity is zero in every clip (``Y``). Only the
order of the frames differs (no ``T_k``): fast then slow, or slow then fast, which is the energy.
Occluded variant: a screen, lower than the wall, hides the bounce; visible variant: no screen.
Both carry the verdict.

Why v6 (probes/energy/README.md "Why v6"): Energy-v5 reversed a vertical bounce. A ball that loses energy at a
bounce falls faster than it rises and its reversal the other way round, so no time reversal of a
vertical bounce balances the sign of the vertical motion, and random pixel and interaction
networks read it (0.00-0.10 or 1.00 per draw on dev seeds 4418 and 8111). A horizontal bounce has
no vertical motion to read.

Why the impact in the middle of its frame interval: an impact at phase ``phi`` of its interval is at
``1 - phi`` backwards, so a predictor that steps over it (constant velocity) misses it by
``(1 - phi)(1 + e) u dt`` forwards and ``phi (1 + e) u dt`` backwards: Energy-v3 handed constant
velocity 0.95 on seed 2026 through that alone (``_slide``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.branch import rollout
from voe.concepts.parts import FLOOR_Y, floor, screen
from voe.sim.rollout import Recording
from voe.sim.scene import FEATURE_NAMES, Body, Scene, Segment

#: Top of the wall, and of the occluded sets' screen: the screen hides the ball (at most 0.9 high
#: on a floor at 0.6) where it meets the wall, and the wall shows above it, so the bounce has a
#: visible cause in both conditions; both stay below the distractor lane (7.6).
WALL_TOP = 3.4
SCREEN_TOP = 2.2
#: Half the wall's thickness (a capsule segment's radius).
WALL_R = 0.08
#: State features that change sign when time runs backwards (velocities).
_ODD = [FEATURE_NAMES.index(n) for n in ("vx", "vy", "omega")]
_Y = FEATURE_NAMES.index("y")


def reverse(rec: Recording) -> Recording:
    """The clip played backwards: frames and presence reversed, velocities negated."""
    states = rec.states[::-1].copy()  # (T, K, F)
    states[..., _ODD] = -states[..., _ODD]
    states[..., _ODD] += 0.0  # no negative zeros: a resting object has the same state either way
    return Recording(rec.frames[::-1].copy(), states, rec.present[::-1].copy(),
                     rec.exists[::-1].copy(), rec.geometry)


def sliding(rec: Recording) -> Recording:
    """Store every vertical velocity, angle and spin as 0, in place: every object slides without
    rolling on the floor or its lane.

    Why: the contact solver leaves a resting body's vertical velocity jittering by one substep of
    gravity (+-0.049), and its angle and spin by round-off (1e-14), in patterns that do not reverse
    into themselves, so a clip and its reversal would differ in the signed vertical velocities (no
    ``Y``) and a model reading states would meet different noise forwards and backwards. Sliding,
    they are 0. (Horizontal velocities are constant between frames here, so the half-substep lag of
    stored velocities, Energy-v5's ``instantaneous``, does not arise.)

    Raises:
        ValueError: an object turned or moved vertically by more than solver noise.
    """
    for name, noise in (("vy", 0.1), ("angle", 1e-6), ("omega", 1e-6)):
        v = rec.states[..., FEATURE_NAMES.index(name)]  # (T, K), NaN where not present
        if np.nanmax(np.abs(v), initial=0.0) > noise:
            raise ValueError(f"energy: an object's {name} reached {np.nanmax(np.abs(v)):.3g}; it should slide")
        v[...] = np.where(np.isnan(v), np.nan, 0.0)
    return rec


#: The impact's phase within its frame interval is centred to this fraction of the two misses' sum,
#: starting the ball up to ``PHASE_STEPS`` quarter substeps of travel earlier or later.
PHASE_TOL = 0.05
PHASE_STEPS = 80


def _miss_gap(truth: np.ndarray, ball: int, dt: float) -> float:
    """``(miss forwards - miss backwards) / (sum)`` of a constant-velocity one-frame predictor at
    the bounce of ``truth (T, K, F)``: 0 when the impact is mid-interval, about ``1 - 2 phi``."""
    x = truth[:, ball, 0].astype(np.float64)  # (T,)
    vx = truth[:, ball, 3].astype(np.float64)
    f = int(np.argmax(vx < 0)) - 1  # last frame going in; f + 1 comes back
    fwd = abs(x[f + 1] - (x[f] + vx[f] * dt))
    rev = abs(x[f] - (x[f + 1] - vx[f + 1] * dt))
    return float((fwd - rev) / max(fwd + rev, 1e-9))


class Energy(Concept):
    name = "energy"
    version = 6
    #: the pair and both clips' left-right mirrors: the reversal slides the other way (v5)
    kind = "mirrored"
    #: v6: a horizontal bounce has no vertical motion, so ``Y`` holds as well (v5 lacked it)
    balance = {"visible": "F+M+P+V+H+D+X+Y", "occluded": "F+M+P+V+H+D+X+Y"}
    #: Energy-v5's vertical bounce was confounded (random networks read the sign of the vertical
    #: motion). v6 balances ``Y``; whether every knowledge-free control is then at chance is
    #: measured on dev seeds (probes/energy/README.md "Controls on v6"): the flag stays until they all are.
    confounded = True

    @staticmethod
    def _distractors(rng: np.random.Generator, n: int, slots: tuple[int, ...]) -> tuple[Body, ...]:
        """The lane's objects slide slowly, all one way, and touch nothing within the clip.

        Why: a contact is not exactly time-symmetric in the simulator (when in its frame it falls
        decides what a frame-level model sees), so a distractor bouncing off a lane wall gave the
        reversed clip away (constant velocity: 0.6 nats per distractor on seed 0, Energy-v3).
        Started at the depth the contact solver settles them to (``SINK``), as the ball is: a body
        placed touching its support sinks on the first substeps, so the first frame alone would sit
        higher and the reversal would move down where the possible clip moves up (no ``Y``).
        """
        out = Concept._distractors(rng, n, slots)
        way = 1.0 if n == 0 or out[0].vx >= 0 else -1.0
        return tuple(d.moved(vx=way * 0.25, y=d.y - Energy.SINK) for d in out)

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        """Speed, restitution, wall position and the frame interval the impact falls in."""
        r = self.ranges
        size = self.uniform(rng, r["size"])
        wall_e = self.uniform(rng, r["wall_elasticity"])
        restitution = self.uniform(rng, r["restitution"])
        return {"main_slots": list(ctx.slots[:1]),
                "look": {"shape": "circle", "width": size, "height": size,
                         "intensity": self.uniform(rng, [0.65, 1.0])},
                "speed": self.uniform(rng, r["speed"]), "restitution": restitution,
                "impact_frame": int(rng.integers(r["impact_frame"][0], r["impact_frame"][1] + 1)),
                "wall_x": self.uniform(rng, r["wall_x"]), "wall_elasticity": wall_e,
                "ball_elasticity": restitution / wall_e,
                "screen_margin": self.uniform(rng, r["screen_margin"])}

    def build(self, p: dict[str, Any], ctx: Context, shift: float = 0.0) -> Scene:
        """The slide, with the ball meeting the wall ``(impact_frame + 1/2) dt`` after the start,
        ``shift`` units further along (``shift`` moves the impact within its frame, ``_slide``)."""
        look, u = p["look"], p["speed"]
        rad = look["width"] / 2
        x0 = p["wall_x"] - rad - u * (p["impact_frame"] + 0.5) * ctx.cfg.dt + shift
        # Started at the depth the contact solver settles it to (one slop below the surface), so
        # that its height is the same on every frame: otherwise the first frame alone sits higher
        # and the reversal moves down where the possible clip moves up (no ``Y``).
        ball = Body(slot=ctx.slots[0], shape="circle", width=look["width"], height=look["height"],
                    x=x0, y=FLOOR_Y + rad - self.SINK, vx=u, vy=0.0, friction=0.0,
                    elasticity=p["ball_elasticity"], intensity=look["intensity"])
        wx = p["wall_x"] + WALL_R
        wall = Segment((wx, FLOOR_Y), (wx, WALL_TOP), WALL_R, 0.0, p["wall_elasticity"], "wall")
        occ = []
        if not ctx.visible:  # hides the ball within `screen_margin` of the wall, and the wall's foot
            x_lo, x_hi = p["wall_x"] - look["width"] - p["screen_margin"], wx + 2 * WALL_R
            occ = [screen((x_lo + x_hi) / 2, x_hi - x_lo, SCREEN_TOP - (FLOOR_Y - 0.3), pad=ctx.pixel)]
        return self.scene(ctx, [ball], [floor(friction=0.0, elasticity=0.0), wall], occ)

    #: How far a body resting on the floor sinks into it (pymunk's collision slop; measured: a ball
    #: dropped onto the floor from touching settles 0.00025 lower on its first substeps).
    SINK = 0.00025

    def _slide(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, np.ndarray, float]:
        """The possible clip with its impact in the middle of a frame interval.

        Why: see the module docstring. The phase is measured as the constant-velocity predictor's
        two misses at the impact, on the simulated states (the contact starts on a substep, so the
        misses move in steps, not smoothly), and the ball is started further or nearer, by a
        quarter substep of travel at a time, until they agree to ``PHASE_TOL`` of their sum.
        """
        slot, h = ctx.slots[0], ctx.cfg.dt / ctx.cfg.substeps
        best = None
        for k in sorted(range(-PHASE_STEPS, PHASE_STEPS + 1), key=lambda k: (abs(k), k)):
            shift = k * p["speed"] * h / 4
            pos, truth = rollout(self.build(p, ctx, shift), ctx.cfg)  # truth: states also while hidden
            if not (truth[:, slot, 3] < 0).any():
                continue
            gap = abs(_miss_gap(truth, slot, ctx.cfg.dt))
            if best is None or gap < best[0]:
                best = (gap, pos, truth, shift)
            if gap < PHASE_TOL:
                break
        if best is None or best[0] >= PHASE_TOL:
            raise ValueError(f"energy: impact phase not centred within {PHASE_STEPS} quarter substeps")
        return best[1], best[2], best[3]

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        slot, T = ctx.slots[0], ctx.cfg.n_frames
        pos, truth, p["start_offset"] = self._slide(p, ctx)
        vx, y = truth[:, slot, 3], truth[:, slot, _Y]  # (T,)
        back = np.flatnonzero(vx < 0)
        if back.size == 0 or not 8 <= back[0] <= T - 8 or not (vx[back[0]:] < 0).all():
            raise ValueError(f"energy: bounce at frame {back[:1]}; adjust `impact_frame` in spec.yaml")
        if np.ptp(y) != 0:
            raise ValueError("energy: the ball's height changed; check SINK")
        impact = int(back[0])  # first frame after the wall has sent the ball back
        sliding(pos)
        # backwards, forward frame impact - 1 (the last one going in) is frame T - impact: the
        # first frame after the reversed bounce, where the ball leaves faster than it came
        return pos, reverse(pos), T - impact
