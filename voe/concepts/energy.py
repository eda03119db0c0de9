"""Energy: a bouncing ball never rises higher than the top of its flight.

Possible: a ball is tossed up (and sideways) so that the top of its flight is ``h`` above the floor;
it falls and bounces once with a restitution below one (ball elasticity times floor elasticity,
pymunk multiplies them), so it rises only to about ``e^2 h``. Impossible: the same clip played
backwards (time reversal): the ball falls from the lower peak, bounces, and rises to ``h``, gaining
energy from nowhere at the bounce. Gravity still points down in the reversed clip (parabolas are
symmetric in time), the frames are exactly those of the possible clip and so are the per-step
changes, the positions, speeds and heights (F+M+P+V+H+D): a per-frame, motion-energy, height or
speed scorer ties exactly. Only the order of the frames differs (no ``T_k``), and only at the
bounce does the reversed clip break a law. Occluded variant: a pillar, higher than the ball
ever gets, hides the bounce; visible variant: no pillar. Both carry the verdict.

Why a single bounce mid-clip: the reversed clip then holds one (energy-gaining) bounce too, and
starts and ends in flight, so nothing but the bounce tells it from a tossed ball. Why the impact
in the middle of its frame interval and the clip starting and ending at the same speed (v4): an
impact early or late in its frame is late or early backwards, and a model judges the possible
clip on its last frame but the reversed one on the possible clip's first; v3 left both as cues
(constant velocity 0.95 on seed 2026, the ``no-inertia`` lesion 0.70). See ``_sample``, ``_toss``.

v2 (a pair: the impact replayed with restitution above one) had the impossible ball higher and
faster than the possible one after the onset: a height and a speed scorer passed it.

Why the mirror (v5): reversing time also reverses the ball's sideways drift, so on v4 the
impossible clip moved left wherever the possible one moved right; a scorer that is not
mirror-symmetric (all ten random pixel networks on seed 4418) separated them by direction alone.
Each set now holds the possible clip, its reversal and the left-right mirrors of both
(``kind = "mirrored"``): every signed horizontal step and velocity occurs on both sides (``X``).
The vertical ones cannot (no ``Y``): a ball that loses energy at the bounce spends longer falling
than rising, and its reversal the other way round; that asymmetry is the violation itself.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.concepts.base import Concept, Context
from voe.concepts.branch import rollout
from voe.concepts.parts import FLOOR_Y, G, floor, screen
from voe.sim.rollout import Recording
from voe.sim.scene import FEATURE_NAMES, Body, Scene, SimConfig

#: Top of the occluded sets' pillar: above the highest ball (4.3), below the distractor lane (7.6).
PILLAR_TOP = 6.5
#: State features that change sign when time runs backwards (velocities).
_ODD = [FEATURE_NAMES.index(n) for n in ("vx", "vy", "omega")]


def reverse(rec: Recording) -> Recording:
    """The clip played backwards: frames and presence reversed, velocities negated."""
    states = rec.states[::-1].copy()  # (T, K, F)
    states[..., _ODD] = -states[..., _ODD]
    states[..., _ODD] += 0.0  # no negative zeros: a resting object has the same state either way
    return Recording(rec.frames[::-1].copy(), states, rec.present[::-1].copy(),
                     rec.exists[::-1].copy(), rec.geometry)


def instantaneous(rec: Recording, ball: int, cfg: SimConfig) -> Recording:
    """Store velocities at the frame's instant, in place, so that time reversal negates them.

    Chipmunk moves a body with its velocity, then updates the velocity (substep h), so a stored
    velocity is the one for the next half substep: played backwards it is not the velocity the
    same integrator needs, and a constant-velocity model found every reversed flight frame 0.9
    nats more surprising (seed 0), gravity or not. The ball is in free flight on every frame (one
    instantaneous bounce): its velocity at the frame's instant is ``v - a h / 2`` with ``a = -g``.
    The distractors rest on their lane, where the contact solver leaves their vertical velocity
    jittering by one substep of gravity (+-0.049) in a pattern that does not reverse into itself:
    resting, it is 0. With both, any integrator meets the same errors forwards and backwards.
    """
    vy = rec.states[..., 4]  # (T, K), NaN where not present
    vy[:, ball] += np.float32(G * cfg.dt / cfg.substeps / 2)
    lane = [k for k in range(cfg.n_slots) if k != ball]
    vy[:, lane] = np.where(np.isnan(vy[:, lane]), np.nan, 0.0)
    return rec


#: The impact's phase within its frame interval is centred to this fraction of the two misses'
#: sum, starting the clip up to ``PHASE_STEPS`` quarter substeps (two frames) earlier or later.
PHASE_TOL = 0.05
PHASE_STEPS = 80


def _miss_gap(truth: np.ndarray, ball: int, cfg: SimConfig) -> float:
    """``(miss forwards - miss backwards) / (sum)`` of a ballistic one-frame predictor at the
    first impact of ``truth (T, K, F)``: 0 when the impact is mid-interval, about ``1 - 2 phi``.

    Velocities are taken at the frame's instant (``instantaneous``), so in flight the ballistic
    predictor is exact both ways and only the impact is missed.
    """
    y = truth[:, ball, 1].astype(np.float64)  # (T,)
    vy = truth[:, ball, 4].astype(np.float64) + G * cfg.dt / cfg.substeps / 2
    f = int(np.argmax(np.diff(np.sign(vy)) > 0))  # last frame falling; f + 1 rises
    dt = cfg.dt
    fwd = abs(y[f + 1] - (y[f] + vy[f] * dt - G * dt ** 2 / 2))
    rev = abs(y[f] - (y[f + 1] - vy[f + 1] * dt - G * dt ** 2 / 2))
    return float((fwd - rev) / max(fwd + rev, 1e-9))


class Energy(Concept):
    name = "energy"
    version = 5
    #: v5: the set also holds both clips' left-right mirrors (``voe.concepts.mirror``): the reversal
    #: drifts the other way, and on v4 every random pixel network followed the drift (seed 4418)
    kind = "mirrored"
    balance = {"visible": "F+M+P+V+H+D+X", "occluded": "F+M+P+V+H+D+X"}
    #: No time reversal balances the vertical direction (``Y``): a ball that loses energy at the
    #: bounce falls faster than it rises and its reversal the other way round, which knowledge-free
    #: random pixel networks read with one sign per network (dev seeds 4418 and 8111: eight of ten
    #: at 0.00-0.10 or 1.00). Until a design balances ``Y``, every energy verdict is confounded.
    confounded = True

    @staticmethod
    def _distractors(rng: np.random.Generator, n: int, slots: tuple[int, ...]) -> tuple[Body, ...]:
        """The lane's objects slide slowly, all one way, and touch nothing within the clip.

        Why: a contact is not exactly time-symmetric in the simulator (when in its frame it falls
        decides what a frame-level model sees), so a distractor bouncing off a lane wall gave the
        reversed clip away (constant velocity: 0.6 nats per distractor on seed 0).
        """
        out = Concept._distractors(rng, n, slots)
        way = 1.0 if n == 0 or out[0].vx >= 0 else -1.0
        return tuple(d.moved(vx=way * 0.25) for d in out)

    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        """Toss height, impact frame and restitution chosen so that the clip starts and ends at the
        same speed, with the impact in the middle of a frame interval.

        Why the same speed: a model scores frames 1..T-1, so the possible clip is judged on its
        last frame and the reversed one on the possible clip's first. On Energy-v3 the toss (about
        5.5 units/s) was much faster than the end of the rebound (1-2 units/s): any model whose
        surprise grows with speed found the reversed clip more surprising without knowing about
        energy (the `no-inertia` lesion, every frame predicted at rest, scored 0.70). Falling at
        ``u`` into the impact at time 0 and leaving it at ``e u``, a clip of length ``L`` from
        ``t_s`` starts rising at ``-u - g t_s`` and ends falling at ``g (t_s + L) - e u``: equal
        when ``t_s = -(L + u (1 - e) / g) / 2``. With the impact at ``(n + 1/2) dt`` after the start
        that fixes the restitution: ``1 - e = ((2n + 1) dt - L) g / u``.
        """
        r = self.ranges
        size = self.uniform(rng, r["size"])
        x = self.uniform(rng, r["x"])
        dt, L = ctx.cfg.dt, (ctx.cfg.n_frames - 1) * ctx.cfg.dt
        drop = self.uniform(rng, r["drop"])
        n = int(rng.integers(r["impact_frame"][0], r["impact_frame"][1] + 1))
        u = float(np.sqrt(2 * G * drop))  # speed into the impact
        restitution = 1 - ((2 * n + 1) * dt - L) * G / u
        floor_e = self.uniform(rng, r["floor_elasticity"])
        return {"main_slots": list(ctx.slots[:1]), "look": {"shape": "circle", "width": size, "height": size,
                         "intensity": self.uniform(rng, [0.65, 1.0])},
                "x": x, "drop": drop, "t_up": (n + 0.5) * dt - u / G, "impact_frame": n,
                "ball_elasticity": restitution / floor_e, "floor_elasticity": floor_e,
                "vx": float(np.sign(5.0 - x)) * self.uniform(rng, r["drift"]),  # towards the centre
                "screen_width": size + self.uniform(rng, r["screen_margin"])}

    def build(self, p: dict[str, Any], ctx: Context, tau: float = 0.0) -> Scene:
        """The toss, the clip starting ``tau`` seconds into it (``tau`` moves the impact within
        its frame interval, see ``_pair``)."""
        look = p["look"]
        vy0 = G * p["t_up"]  # tossed up so that the top of its flight is `drop` above the floor
        y0 = FLOOR_Y + p["drop"] - vy0 ** 2 / (2 * G) + look["height"] / 2
        ball = Body(slot=ctx.slots[0], shape="circle", width=look["width"], height=look["height"],
                    x=p["x"] + p["vx"] * tau, y=y0 + vy0 * tau - G * tau ** 2 / 2,
                    vx=p["vx"], vy=vy0 - G * tau, friction=0.0, elasticity=p["ball_elasticity"],
                    intensity=look["intensity"])
        # a pillar centred where the ball lands, higher than the ball ever gets but below the
        # distractor lane: it hides the bounce, and no distractor passes behind it (one going in
        # forwards comes out of it backwards, which a model may charge as a new object)
        x_land = p["x"] + p["vx"] * (p["t_up"] + float(np.sqrt(2 * p["drop"] / G)))
        occ = [] if ctx.visible else [screen(x_land, p["screen_width"], PILLAR_TOP - (FLOOR_Y - 0.3), pad=ctx.pixel)]
        return self.scene(ctx, [ball], [floor(friction=0.0, elasticity=p["floor_elasticity"])], occ)

    def _toss(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, np.ndarray, float]:
        """The possible clip with its impact in the middle of a frame interval.

        Why: an impact at phase ``phi`` of its frame interval is at ``1 - phi`` backwards, so a
        predictor that steps over it (constant velocity, a ballistic one) misses by
        ``(1 - phi)(1 + e) v dt`` forwards and ``phi (1 + e) v dt`` backwards: on Energy-v3 the
        reversed clip was more surprising in most sets for that reason alone (constant velocity
        0.95 on seed 2026). The phase is measured as the ballistic predictor's two misses at the
        impact, on the simulated states, and the clip is started later (or earlier) along the
        same toss, by quarter substeps (the contact starts on a substep, so the misses move in
        steps, not smoothly), until they agree to ``PHASE_TOL`` of their sum.
        """
        slot, h = ctx.slots[0], ctx.cfg.dt / ctx.cfg.substeps
        best = None
        for k in sorted(range(-PHASE_STEPS, PHASE_STEPS + 1), key=lambda k: (abs(k), k)):
            tau = k * h / 4  # quarter substeps: where in a substep the contact starts matters too
            pos, truth = rollout(self.build(p, ctx, tau), ctx.cfg)  # truth: states also while hidden
            gap = abs(_miss_gap(truth, slot, ctx.cfg))
            if best is None or gap < best[0]:
                best = (gap, pos, truth, tau)
            if gap < PHASE_TOL:
                break
        if best[0] >= PHASE_TOL:
            raise ValueError(f"energy: impact phase not centred within {PHASE_STEPS} quarter substeps "
                             f"(best miss gap {best[0]:.3f})")
        gap, pos, truth, tau = best
        return pos, truth, tau

    def _pair(self, p: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        slot, T = ctx.slots[0], ctx.cfg.n_frames
        pos, truth, p["start_offset"] = self._toss(p, ctx)
        vy = truth[:, slot, 4]  # (T,)
        falling = int(np.argmax(vy < 0))
        rising = np.flatnonzero(vy[falling:] > 0) + falling
        if rising.size == 0 or not 8 <= rising[0] <= T - 8:
            raise ValueError(f"energy: first impact at frame {rising[:1]}; adjust `drop`/`t_up` in spec.yaml")
        later = np.flatnonzero(np.diff(np.sign(vy[rising[0]:])) > 0)
        if later.size:
            raise ValueError("energy: the ball bounces twice; shorten the rebound in spec.yaml")
        impact = int(rising[0])  # first frame after the floor has sent the ball back up
        instantaneous(pos, slot, ctx.cfg)
        # backwards, forward frame impact - 1 (the last one falling) is frame T - impact: the first
        # frame after the reversed bounce, where the ball rises faster than it fell
        return pos, reverse(pos), T - impact
