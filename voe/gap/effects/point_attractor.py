"""An attracting point of unknown position and strength: a = k (p - r) / (|p - r|^2 + s^2)^(3/2).

Why: a hidden magnet or a local dip pulls bodies toward a place. The inverse-square law is
softened over s = 0.1 m so the fit stays smooth when a body passes close to the point. The
position enters nonlinearly, so the fit screens a grid of starts (see ``starts``) together with
the flight-regression starts and fits from the most promising.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState

_SOFT = 0.1  # m


class PointAttractor(Effect):
    name = "point_attractor"
    mass_proportional = True
    param_names = ("k", "px", "py")
    units = ("m^3/s^2", "m", "m")
    contexts = ("region",)
    summary = "bodies are pulled toward a point (a hidden attractor)"
    acts = "region"
    bench_scene = "arena"
    # the cost has several valleys (bench case 5151034: the regression start near the true point
    # but 2x too strong cost more than zero strength on the quick screen, and Powell started at
    # zero strength never moved): fit from the two most promising starts, keep the better
    multi_start = 2
    # near the point the pull rises and falls within a tenth of a second; regression starts from
    # briefly smoothed flight accelerations land in the true valley where the grid's 3.8 m
    # spacing and the 0.25 s smoothing do not (``voe.gap.prefit.FINE_HALF``; development cases
    # 7857008 and 7857047 ended ``unexplained`` with the attractor fitted in another valley)
    fine_flight = True
    # a point at infinity with k / |p - r|^2 held fixed pulls with one constant force: a fitted
    # point at its search bound stands for ``constant_acceleration`` (``Effect.at_limit``)
    limit_name = "constant_acceleration"
    limit_params = (1, 2)

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        d = p[None, 1:3] - state.pos  # (B, 2)
        r2 = np.add.reduce(d * d, axis=1, keepdims=True) + _SOFT**2  # np.sum(d**2, ...) to the bit, cheaper per kick
        return state.mass[:, None] * p[0] * d / r2**1.5, np.zeros_like(state.angle)

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        """A 4 x 3 grid of positions at two strengths (24 starts, screened on a third of the windows).

        Why beyond the recorded region: bodies are pulled *toward* the point, but a thrown ball
        arcs below a point above it and never reaches it, so the point can lie above (and half a
        metre beside) every recorded position. Development case 7741034 (true point at y = 1.11 m,
        highest recorded y 0.96 m): from the old 3 x 3 grid over the recorded region, and from the
        two flight-regression starts (accelerations twice-differenced from 1 mm noise), the fit
        settled in a valley with k = 8.5 at train cost 100269 (truth: 11540) and the attractor lost
        to ``constant_acceleration``; with this grid it reaches cost 33464 and a selection gain of
        0.59 against constant_acceleration's 0.37.
        """
        span_y = max(float(ctx.hi[1] - ctx.lo[1]), 1.0)
        xs = np.linspace(ctx.lo[0] - 0.5, ctx.hi[0] + 0.5, 4)
        ys = np.linspace(ctx.lo[1], ctx.hi[1] + span_y, 3)
        return [np.array([k, x, y]) for k in (0.5, 2.0) for x in xs for y in ys]

    def scale(self, ctx: FitContext) -> np.ndarray:
        size = float(np.max(ctx.hi - ctx.lo))
        return np.array([0.5, 0.2 * size, 0.2 * size])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        span = ctx.hi - ctx.lo + 1.0
        return (np.array([0.0, ctx.lo[0] - span[0], ctx.lo[1] - span[1]]),
                np.array([100.0, ctx.hi[0] + span[0], ctx.hi[1] + span[1]]))

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        return np.array([rng.uniform(0.5, 2.0), rng.uniform(-2, 2), rng.uniform(0.5, 2.0)]), None
