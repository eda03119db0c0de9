"""Fit one candidate effect's parameters on training windows and score it on held-out windows.

Why: every hypothesis is judged the same way. Parameters are fitted with
scipy (bounded Brent or Powell) on multiple-shooting residuals standardised by the expected
residual of a correct model (so noise, not metres, sets the scale) with a soft-L1 loss that keeps
a few chaotic residuals from dominating, and a window far costlier than the median window counted
only as a log (``window_tail``), so that one chaotic window cannot either. The verdict on a
hypothesis is its held-out RMSE, never its training cost, so a flexible effect gains nothing by
overfitting.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from voe.gap.effects.base import Effect, EffectSum, FitContext
from voe.gap.prefit import prefit_starts
from voe.gap.shooting import Shooter, Window, rmse, window_sse

WALK_STEPS = 8  # steps past a one-parameter grid's end (``_walk``), each 3x the last: 10 -> ~7e4 scales
_XATOL = 0.01  # bounded Brent's absolute tolerance, in parameter scales


@dataclass(frozen=True)
class FitConfig:
    """How hard to try. ``max_nfev`` bounds cost evaluations per candidate and parameter."""

    max_nfev: int = 12
    refine_nfev: int = 20
    f_scale: float = 3.0  # soft-L1 knee, in units of the expected residual
    window_knee: float | None = 10.0  # above this many median windows' cost a window counts as a log (``window_tail``)


@dataclass(frozen=True)
class FitResult:
    """A fitted candidate: the effect, its parameters, and held-out RMSE after fitting."""

    effect: Effect
    params: np.ndarray
    train_cost: float
    heldout_rmse: float
    window_sse: np.ndarray | None = None  # (W,) held-out squared error per window
    fold_params: tuple[np.ndarray, ...] = ()  # per fold (see voe.gap.folds); () means (params,)
    train_full: bool = False  # train_cost is the cost on every fold's full training windows (not a focused subset)
    grid_end: bool = False  # a one-parameter fit left where its walk past the coarse grid ran out of steps, inside
    # the bounds, the cost still falling (``Fitter._scalar``, ``_walk``; ``voe.gap.grid_end.beyond_grid``)

    def __post_init__(self) -> None:
        if not self.fold_params:
            object.__setattr__(self, "fold_params", (self.params,))


class Fitter:
    """Fits effects on ``train`` windows and scores them on ``test`` windows.

    Args:
        shooter: simulates windows.
        sigma: (B, 3) noise floor.
        train, test: windows.
        ctx: problem description for starting points and scales.
        pool: every training window ``train`` was subsampled from; a ``sparse`` effect is fitted
            on the pool's windows where it changes the prediction (at most ``len(train)`` of them).
    """

    def __init__(self, shooter: Shooter, sigma: np.ndarray, train: list[Window], test: list[Window],
                 ctx: FitContext, config: FitConfig | None = None, pool: list[Window] | None = None) -> None:
        self.shooter, self.train, self.test, self.ctx = shooter, train, test, ctx
        self.config = config or FitConfig()
        self.sigma, self.pool = sigma, pool
        self._weights = [1.0 / shooter.sigma_pred(w, sigma) for w in train]  # each (n, B, 3)
        self._memo: dict[tuple, float] = {}  # (effect, params) -> training cost

    def _on(self, train: list[Window], weights: list[np.ndarray] | None = None) -> Fitter:
        """This fitter with other training windows (a shallow copy); ``weights`` if already known."""
        if weights is None:
            weights = [1.0 / self.shooter.sigma_pred(w, self.sigma) for w in train]
        sub = Fitter.__new__(Fitter)
        sub.__dict__.update(self.__dict__, train=train, _weights=weights, _memo={})
        return sub

    def unfocused(self) -> Fitter:
        """This fitter without its pool: every fit on the training windows, a ``sparse`` newest
        part's too (``focused`` returns self). Why: see ``voe.gap.check.check_step``."""
        sub = self._on(self.train, self._weights)
        sub.pool = None
        return sub

    def focused(self, effect: Effect, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, scale: np.ndarray) -> Fitter:
        """For a ``sparse`` newest part of ``effect``: a fitter on pool windows where moving that
        part's parameters by 3 scales changes the prediction by more than a third of the noise
        floor, as many as the training budget (``len(self.train)``); otherwise self.

        Why: a mass acts only in the few windows where bodies collide. A random subsample of
        the training windows held two or three such collisions, one of them chaotic, and the fit
        settled on a mass ratio on the wrong side of nominal. The pool is screened in a fixed
        random order, after the effect's own geometric screen (``Effect.may_act``), and
        screening stops once the budget is filled (two rollouts per window; the windows are
        simulated in batches of the hits still missing, so exactly as many as one by one).
        """
        new = effect.parts[-1]
        if not new.sparse or not self.pool:
            return self
        n = new.n_params
        probe = x0.copy()
        probe[-n:] = np.clip(x0[-n:] + 3 * scale[-n:], lo[-n:], hi[-n:])
        if np.allclose(probe, x0):  # at the upper bound: probe below instead
            probe[-n:] = np.clip(x0[-n:] - 3 * scale[-n:], lo[-n:], hi[-n:])
        tol2 = (float(np.min(self.sigma[:, :2])) / 3) ** 2
        sh, hit = self.shooter, []
        budget = len(self.train) or len(self.pool)  # no training windows: every window that moves
        order = (w for w in (self.pool[i] for i in np.random.default_rng(len(self.pool)).permutation(len(self.pool)))
                 if new.may_act(sh.scene, sh.episodes[w.ep].pose[w.k0:w.k1 + 1]))
        while len(hit) < budget:
            # the next windows, as many as hits are still missing, side by side (each as if
            # alone): never past where a one-by-one screen would stop, so the same windows
            batch = list(itertools.islice(order, budget - len(hit)))
            if not batch:
                break
            for w, a, b in zip(batch, sh.residuals(batch, effect, probe), sh.residuals(batch, effect, x0), strict=True):
                moved = float(np.nanmean((a - b) ** 2))
                if not np.isfinite(moved) or moved > tol2:
                    hit.append(w)
        return self._on(sorted(hit, key=lambda w: (w.ep, w.k0))) if hit else self

    def window_costs(self, effect: Effect | None, params: np.ndarray | None) -> np.ndarray:
        """(W,) soft-L1 cost of each training window's residuals divided by their expected size."""
        fs = self.config.f_scale
        out = []
        for r, wt in zip(self.shooter.residuals(self.train, effect, params), self._weights, strict=True):
            z = np.nan_to_num((r * wt).reshape(-1), nan=1e6, posinf=1e6, neginf=-1e6)
            out.append(float(np.sum(2 * fs**2 * (np.sqrt(1 + (z / fs) ** 2) - 1))))
        return np.array(out)

    def heldout(self, effect: Effect | None, params: np.ndarray | None) -> float:
        """Held-out RMSE in metres (x, y and angle times sqrt(I/m))."""
        return rmse(self.shooter.residuals(self.test, effect, params))

    def heldout_sse(self, effect: Effect | None, params: np.ndarray | None) -> np.ndarray:
        """(W,) held-out sum of squared residuals per window (for the paired bootstrap)."""
        return window_sse(self.shooter, self.test, effect, params)

    def cost(self, effect: Effect | None, params: np.ndarray | None) -> float:
        """Training cost: the windows' soft-L1 costs, each far above the median window's grown only
        as a log (``window_tail``); remembered per effect and exact parameter vector.

        Why remember: scipy's Powell starts every line search by re-evaluating the point it
        stands on, a clipped step can land on a point already simulated. A repeat costs a dictionary lookup instead of a rollout of
        every training window, and the optimiser sees the same values, so it takes the same path.
        The memory lasts one ``fit``.
        """
        key = (effect_key(effect), None if params is None else np.asarray(params, dtype=float).tobytes())
        if key in self._memo:
            return self._memo[key]
        c = float(np.sum(window_tail(self.window_costs(effect, params), self.config.window_knee)))
        self._memo[key] = c = c if np.isfinite(c) else 1e300
        return c

    def fit(self, effect: Effect, starts: list[np.ndarray] | None = None, max_nfev: int | None = None) -> FitResult:
        """Fit ``effect`` from the most promising of ``starts`` (default: the effect's own).

        Why not Gauss-Newton: windows with collisions make the residual jump with the
        parameters, and ``least_squares`` then rejects step after step. The soft-L1 cost is
        smooth at the scale that matters, so a derivative-free search is both more reliable and
        cheaper: a coarse grid plus bounded Brent for one parameter, bounded Powell in units of
        each parameter's scale for several.
        """
        if effect.n_params == 0:
            sse = self.heldout_sse(effect, np.zeros(0))
            return FitResult(effect, np.zeros(0), self.cost(effect, np.zeros(0)),
                             float(np.sqrt(sse.sum() / max(self._n_test, 1))), sse, train_full=True)
        self._memo = {}  # per fit: the work, and the rollout count, must not depend on which process fitted before
        nfev = max_nfev or self.config.max_nfev
        lo, hi = effect.bounds(self.ctx)
        scale = effect.scale(self.ctx)
        starts = list(starts) if starts is not None else effect.starts(self.ctx)
        starts = [np.clip(s, lo, hi) for s in starts]
        n_fit = effect.parts[-1].multi_start if len(starts) > 1 else 1
        if len(starts) > 1:  # rank starts by training cost on a third of the windows
            every = 1 if effect.parts[-1].screen_all else 3
            sub = self._on(self.train[::every], self._weights[::every])
            costs = [sub.cost(effect, s) for s in starts]
            starts = [starts[i] for i in np.argsort(costs, kind="stable")[:n_fit]]
        best = None
        for x0 in starts:  # one start, or an effect's ``multi_start`` most promising ones
            on = self.focused(effect, x0, lo, hi, scale)
            # each part where it acts: the rest held on a sparse part's windows, earlier sparse parts on the training windows
            lo_x, hi_x = held(effect, x0, lo, hi) if on is not self else held_sparse(effect, x0, lo, hi)
            end = False
            if effect.n_params > 1 and effect.parts[-1].n_params == 1:
                x0 = on._screen_guess(effect, x0, lo_x, hi_x, scale)
            if effect.n_params == 1:
                x, cost, end = on._scalar(effect, x0, lo_x, hi_x, scale, nfev)
            else:
                x, cost = on._powell(effect, x0, lo_x, hi_x, scale, nfev)
            settle = on is not self and any(not p.sparse for p in effect.parts[:-1])
            if settle:  # then the earlier dense parts on the training windows, every sparse part held
                x, cost = self._powell(effect, x, *held_sparse(effect, x, lo, hi, newest=True), scale, nfev)
            if len(starts) > 1:  # compare on the full training windows, not a focused subset
                cost = self.cost(effect, x)
            if best is None or cost < best[1]:
                best = (x, cost, len(starts) > 1 or on is self or settle, end)
        x, cost, full, end = best
        sse = self.heldout_sse(effect, x)
        return FitResult(effect, x, cost, float(np.sqrt(sse.sum() / self._n_test)), sse, train_full=full, grid_end=end)

    @property
    def _n_test(self) -> int:
        return sum((w.k1 - w.k0 + 1) * self.shooter.scale.size for w in self.test)

    def _screen_guess(self, effect: Effect, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                      scale: np.ndarray) -> np.ndarray:
        """``x0``, or, if it predicts the training windows worse than the model without ``effect``'s
        newest part (a one-parameter part), ``x0`` with that part moved to the best point of its
        coarse grid (``scalar_grid``), the other parts held.

        Why: the greedy search extends the current model, so a candidate's start is meant to be
        that model again (a force of zero strength adds nothing). A material whose single value
        stands for several bodies cannot be: ``restitution`` starts at the bodies' mean elasticity,
        which changes every body whose own value differs, so the start is a guess, worse than the
        model it extends, and Powell from it can stop in a valley between. Development case 8657134
        (``linear_drag`` 0.374 and ``restitution`` 0.672, nominal elasticities 0.534 and 0.230): on
        top of round 0's drag the start (mean 0.382) cost 60838 against the drag's 44775, Powell
        stopped at 0.412 (54245) while 0.672 costs 5868, the round gained nothing and restitution
        was never named. A one-parameter fit screens this grid (``_scalar``); a guessed start in a
        larger model now gets the same screen. A force's start from the free-flight regression
        (``voe.gap.prefit``) is a guess too, screened when it predicts worse than the model; a
        start that reproduces the model (zero strength, ``mass``'s ratio 1) costs exactly as much
        and is left alone.
        """
        c0 = self.cost(effect, x0)
        if c0 <= self.cost(EffectSum(effect.parts[:-1]), x0[:-1]):
            return x0
        grid = scalar_grid(effect, x0[-1:], lo[-1:], hi[-1:], scale[-1:])
        points = [np.concatenate([x0[:-1], [g]]) for g in grid]  # (G, P)
        costs = [self.cost(effect, x) for x in points]
        i = int(np.argmin(costs))
        return points[i] if costs[i] < c0 else x0

    def _scalar(self, effect, x0, lo, hi, scale, nfev) -> tuple[np.ndarray, float, bool]:
        """Grid, then bounded Brent between the best grid point's neighbours; a minimum at the
        grid's outermost point inside the bounds is followed outward (``_walk``). Also whether the
        value is still where a walk ran out of steps with the cost falling (``FitResult.grid_end``).

        Why the walk: the grid reaches 10 scales from the start, and a true value can lie further
        out. ``joint_friction`` starts near zero with a scale of 1/1000 of the gravity torque, and
        every true value of the bench's prior (1-3 % of it) lies 10-30 scales out: on development
        seed 6219 the first fit of the true effect stopped at the grid's end in 7 of 10 cases
        (6219018: 0.0179 against 0.0450, selection gain 0.383 where a fit from the truth gains
        0.694), and only the refine step, given to the winner alone, went on. Stopping there is
        not a property of the effect but of the grid, so every one-parameter fit walks on.
        """
        grid = scalar_grid(effect, x0, lo, hi, scale)
        costs = [self.cost(effect, np.array([g])) for g in grid]
        i = int(np.argmin(costs))
        it = max(3, nfev - len(grid))
        x, fx = _bracketed(self, effect, grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)], grid[i], costs[i],
                           it, scale)
        at_end = (len(grid) > 1 and i in (0, len(grid) - 1) and lo[0] < grid[i] < hi[0]
                  and abs(x - grid[i]) <= 2 * _XATOL * scale[0])
        if not at_end:
            return np.array([x]), fx, False
        inner = grid[1] if i == 0 else grid[-2]
        return _walk(self, effect, inner, grid[i], costs[i], (x, fx), lo, hi, scale, it)

    def _powell(self, effect, x0, lo, hi, scale, nfev) -> tuple[np.ndarray, float]:
        """Powell's method in units of each parameter's scale, bounds enforced by clipping.

        Why not scipy's bounded Powell: with bounds, each line search is a bounded Brent over the
        whole feasible segment, which can settle in another valley *worse than the current
        point* (seen: an attractor fitted to 1 cm moved 2 m away, cost up 20-fold). Unbounded
        line searches bracket from the current point, so every step is an improvement; the
        clip keeps every simulated parameter inside the bounds.
        """
        lo_u, hi_u = lo / scale, hi / scale

        def f(u: np.ndarray) -> float:
            return self.cost(effect, np.clip(u, lo_u, hi_u) * scale)

        u0 = np.clip(x0 / scale, lo_u, hi_u)
        res = minimize(f, u0, method="Powell", options={"maxfev": max(nfev * effect.n_params, 40), "xtol": 0.01,
                                                        "ftol": 1e-4, "direc": 0.3 * np.eye(len(u0))})
        return np.clip(res.x, lo_u, hi_u) * scale, float(res.fun)


def _bracketed(fitter: Fitter, effect: Effect, a: float, b: float, x: float, fx: float, it: int,
               scale: np.ndarray) -> tuple[float, float]:
    """Bounded Brent on [a, b] (at most ``it`` iterations); its minimum if lower than ``fx`` at
    ``x`` (a point already costed), else (x, fx)."""
    if b - a <= 0:
        return float(x), float(fx)
    res = minimize_scalar(lambda v: fitter.cost(effect, np.array([v])), bounds=(a, b), method="bounded",
                          options={"maxiter": it, "xatol": _XATOL * scale[0]})
    return (float(res.x), float(res.fun)) if res.fun < fx else (float(x), float(fx))


def _walk(fitter: Fitter, effect: Effect, inner: float, end: float, f_end: float, best: tuple[float, float],
          lo: np.ndarray, hi: np.ndarray, scale: np.ndarray, it: int) -> tuple[np.ndarray, float, bool]:
    """Follow a one-parameter cost that still falls at the grid's end ``end`` (its grid
    neighbour ``inner``) outward, each step three times the last (at most ``WALK_STEPS``,
    clipped to the bounds), until it rises; then bounded Brent between the last two points
    before the rise and the rise. ``best`` (x, cost) is the grid's own result, kept if lower.
    """
    prev, rise = inner, None
    for _ in range(WALK_STEPS):
        nxt = float(np.clip(end + 3 * (end - prev), lo[0], hi[0]))
        if nxt == end:  # at a bound
            break
        c = fitter.cost(effect, np.array([nxt]))
        if c >= f_end:
            rise = nxt
            break
        prev, end, f_end = end, nxt, c
    x, fx = (end, f_end) if f_end < best[1] else best
    if rise is not None:  # the minimum lies between prev and the rise
        x, fx = _bracketed(fitter, effect, *sorted((prev, rise)), x, fx, it, scale)
        return np.array([x]), fx, False
    # no rise: the walk stopped at a bound (the value there) or ran out of steps inside the bounds
    return np.array([x]), fx, bool(lo[0] < end < hi[0] and x == end)


def window_tail(costs: np.ndarray, knee: float | None) -> np.ndarray:
    """(W,) each window's cost, the part above ``knee`` times the median window's grown as a log
    (``m (1 + log(c / m))`` above ``m``: continuous, with slope 1 at the knee); as is for ``None``.

    Why: soft-L1 bounds each residual's pull, not a window's. A window whose outcome flips with a
    tiny state error (a collision, the double pendulum's chaotic stretch) can cost a hundred
    times the median window at the true parameters, and the fit then trades every other window
    for it. Development case 4446106 (true constant acceleration (-0.584, -0.086)): at the
    truth one of 8 fitting windows cost 141 times the median, the fit went to (-0.723, -0.013),
    where that window was fine and the median window 8 times worse, and the selection windows
    favoured the truth (gain 95.5 % against 83.6 %), so ``spring_anchor`` (94.0 %) was named;
    the same on 4593002 (one window 103 times the median at the truth) and 2758005 (134 times:
    the joint friction fitted to 0). Only windows far above the median are compressed, so a
    weak effect carried by a few windows a few times above the noise keeps its pull (a log cap
    on every window above its own residual count, tried in session 18, lost 2758011).
    """
    if knee is None or costs.size == 0:
        return costs
    m = knee * max(float(np.median(costs)), 1e-12)
    return np.where(costs > m, m * (1 + np.log(np.maximum(costs, m) / m)), costs)


def held(effect: Effect, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bounds (P,) each that hold every part but the newest at ``x0``: for a fit on the windows
    ``Fitter.focused`` chose for a sparse newest part.

    Why: those windows are the few where that part acts (collisions between bodies); they say
    little about the parts already in. Fitted there too, a rolling resistance (an effect of
    every rolling stretch) went to 0 under a mass on development case 8586058 (truth 0.045)
    and to 0.142 on 1531007 (truth 0.038). Each part is fitted where it acts: the earlier
    parts on the training windows of their own rounds, the sparse one on its own windows.
    """
    n = effect.parts[-1].n_params
    lo, hi = lo.copy(), hi.copy()
    lo[:-n], hi[:-n] = x0[:-n], x0[:-n]
    return lo, hi


def scalar_grid(effect: Effect, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """The sorted coarse grid a one-parameter fit screens around ``x0`` (the newest part's
    ``Effect.grid``), clipped to the bounds; offsets below a zero lower bound collapse into one
    point. Shared by ``Fitter._scalar`` and the check's ``beyond_grid``, which asks the next point
    of the same grid beyond a value left at its end."""
    return np.unique(np.clip(effect.parts[-1].grid(float(x0[0]), float(scale[0])), lo[0], hi[0]))


def effect_key(effect: Effect | None) -> tuple:
    """What decides an effect's physics: its parts' classes and bodies (not the object's identity,
    which Python may reuse after an effect is freed)."""
    return () if effect is None else tuple((type(e).__module__, type(e).__qualname__, e.bodies) for e in effect.parts)


def extend(current: Effect | None, params: np.ndarray, cand: Effect, ctx: FitContext) -> tuple[Effect, list[np.ndarray]]:
    """``current + cand`` and its starting points (current parameters kept, cand's starts added).

    A force effect's starts are first refined by a regression on the free-flight accelerations
    that ``current`` leaves unexplained (``prefit_starts``), and for an effect that declares
    ``fine_flight`` also by one on accelerations smoothed over a short span; its own grid is kept
    only when it is small, so the simulator fit starts from at most a handful of points, or when
    the effect declares several valleys (``multi_start > 1``): twice-differenced accelerations
    are noisy, and a regression start can sit in the wrong valley (case 7741034), so it joins
    the grid in ``Fitter.fit``'s screen instead of replacing it.
    """
    own = cand.starts(ctx)
    lo, hi = cand.bounds(ctx)
    pre = prefit_starts(cand, own, lo, hi, cand.scale(ctx), ctx.flight, ctx.scene, current, params)
    if cand.fine_flight:  # a force that changes fast: also regress on the briefly smoothed samples
        pre += prefit_starts(cand, own, lo, hi, cand.scale(ctx), ctx.flight_fine, ctx.scene, current, params)
    if pre:  # an effect with several valleys keeps its grid: the regression is one more start, screened with it
        own = pre + (own if len(own) <= 2 or cand.multi_start > 1 else [])
    if current is None:
        return cand, own
    combo = EffectSum(current.parts + cand.parts)
    return combo, [np.concatenate([params, s]) for s in own]


def held_sparse(effect: Effect, x0: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                newest: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Bounds (P,) that hold every earlier ``sparse`` part at ``x0``: for a fit on the training
    windows (the newest part dense, or no pool to focus on).

    Why: the mirror of ``held``. A sparse part (a mass, felt only where bodies collide) was fitted
    on its own windows, the collisions; a random subsample of the training windows holds few of
    them, some chaotic, and says little about it. Fitted there jointly with a later dense part,
    it moves to wherever those few collisions point. Development case 6685133 (a rolling
    resistance 0.0565 and a box 2.10 times heavier): round 1 fitted ``mass[box]`` 2.018 on its
    collision windows (gain 73 %); in round 2 ``rolling_resistance`` fitted jointly on the
    training windows moved the mass to 0.947 (a lighter box) and gained -237 %, so no second
    effect was accepted; with the mass held, ``rolling_resistance`` fits 0.0608 and gains 23.3 %
    (threshold 5 %). Each part is fitted where it acts.

    ``newest``: the newest part is held too, if sparse: the second step of a sparse newest part's
    fit, which moves only the earlier dense parts, on the training windows. Why: the earlier parts
    were fitted without the new one and absorbed some of its effect where they could. Held while
    the new sparse part is fitted on its own windows (``held``), they stay biased, and the pair is
    judged against candidates that refit every part jointly. Development case 8367135
    (``quadratic_drag`` 0.193 and ``friction`` 1.43): round 0 fitted the drag to 0.187; in round 1
    ``friction`` on top, the drag held, fitted 1.35 and gained 39.8 % on the selection windows,
    where the truth gains 54.5 %, and ``friction_region``, a dense part that refits the drag (to
    0.198), won with 48.0 % over x -0.75..2.85 m (at x -5..8 m it gains the same: the interval
    held every sliding contact). One step of block coordinate descent: each part is still fitted
    where it acts, the earlier ones given the new one.
    """
    lo, hi = lo.copy(), hi.copy()
    i = 0
    for part in effect.parts if newest else effect.parts[:-1]:
        if part.sparse:
            lo[i:i + part.n_params], hi[i:i + part.n_params] = x0[i:i + part.n_params], x0[i:i + part.n_params]
        i += part.n_params
    return lo, hi
