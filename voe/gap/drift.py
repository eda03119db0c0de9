"""Is a named effect the same at every time? A structural-break (Chow) test on its parameters.

Why: every library effect is constant in time. Physics that varies in time (a wind gusting,
development case 6263064) can still be fitted in part by a constant effect (there
``constant_acceleration`` cut the selection error by 28 %), which then passes every other test
and names a library effect for physics outside the library. If the effect were right, its
parameters fitted on the windows at one time of the episodes and on all the others would agree
within what the windows determine; a constant fitted to a gust differs between them by a sizeable
fraction of the gust. The test is Chow's (1960): one model fitted on two subsamples, the
difference of the estimates against its sampling spread.

Each subsample's estimate is one Gauss-Newton step from the fit, from per-window curvatures and
gradients as the intervals use them (``voe.gap.uncertainty.window_terms``): no new fits. Since
session 11 each window's estimated start velocity is profiled out of its terms
(``voe.gap.nuisance``): a rolling ball's start estimate breaks the rolling constraint, and the
slip it leaves read as a drag changing in time (development case 1531045: a true linear drag,
c = 0.183, dropped at z = 9.8, the windows at 2.5 s giving 0.119; profiled they give 0.175
against 0.190, z = 0.6). Checked on dev seeds (each effect at its true parameters, and a
constant acceleration fitted by Gauss-Newton to each gust): docs/gap-findings.md. The
windows are 0.5 s long, every 0.25 s (half the fitting windows: a gust of about a second
averages out over a 1 s window). Subsamples: the windows centred in one 0.25 s slot of episode
time against all others, for every slot. The spread of a difference is a bootstrap within time
slots (at least the Gauss-Newton steps' own covariance); a part *drifts* if some parameter
differs by more than the Student-t critical value (degrees of freedom from the smaller side's
windows) at a family-wise 5 %, Bonferroni over slots and parameters. A drifting effect is not
reported (``gap.json`` lists it under ``dropped`` with both values); with nothing left the
verdict is ``unexplained``, with where and when.

Checked on development cases, each effect at its true parameters: no drift in 50 single truths
of seeds 7 and 8 nor in the four compound truths of 6263055-58; a constant acceleration fitted
(pooled Gauss-Newton) to each of the eight gusts of seeds 6263 and 5151 drifts in seven. Not
split by episode: windows of one episode share its start-state errors, and with a window
bootstrap a true restitution, point attractor and constant acceleration (7010, 7021, 7015)
differed between the first and second three fitting episodes at z = 4.4-4.6. A significant
difference must also be material, ``MATERIAL`` of the part's strength (``material``), as in flight:
right effects lost 11-18 % differences to start-state errors the windows' spread does not show.

The bootstrap sd is widened ``voe.gap.parametric.SPREAD`` times, the factor by which resampled
windows and replicates understate the estimator's spread (the coverage calibrations: intervals
from the window bootstrap held the truth in 70/96 dev cases of seeds 0-7 as they were, 90/96 at
2x, ``voe.gap.uncertainty``; the parametric replicates 60/72 and 68/72 on seeds 8-13,
``voe.gap.parametric``). One constant for both: the drift test compares
two estimates of the same estimator, so it needs the same spread the intervals need. Session 15,
development case 8587095: a true joint damping (0.0486, expressed in 19 of 20 windows) was dropped
at z = 5.8 (critical 4.8) for 0.0324 in the six windows centred 2.2 s against 0.0477 elsewhere,
32 % of its strength; widened, z = 2.9, and it is reported (0.0481). A constant fitted to a gust
or a floor patch is caught mostly in flight (``voe.gap.drift_flight``, t-tests on one residual per
episode and slot, each slot against the rest and the time before each slot boundary against the
time after, not widened: that spread is measured across independent units).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from voe.gap.check import Checked, model_intervals, verify_on_test
from voe.gap.drift_base import MATERIAL, Drift, critical
from voe.gap.drift_flight import flight_drift, flight_movers
from voe.gap.effects.base import Effect, EffectSum, FitContext
from voe.gap.fit import FitResult, effect_key
from voe.gap.folds import as_sum, without
from voe.gap.nuisance import profiled_terms
from voe.gap.parallel import Ahead
from voe.gap.parametric import SPREAD
from voe.gap.prefit import flight_samples
from voe.gap.shooting import Shooter, Window, make_windows
from voe.gap.stages import GapConfig, Location, Problem, Search, fit_context
from voe.gap.uncertainty import established, window_terms

SLOT = 0.25  # s of episode time (the windows' stride): windows centred within one slot form a subsample
N_BOOT = 200
MIN_WINDOWS = 3  # per side: the bootstrap spread of two windows can be near zero by chance


def split_estimates(hs: np.ndarray, gs: np.ndarray, params: np.ndarray, mask: np.ndarray, sl: slice,
                    rng: np.random.Generator, other: np.ndarray | None = None, scale: np.ndarray | None = None,
                    strata: np.ndarray | None = None,
                    spread: float = SPREAD) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """One Gauss-Newton step of the parameters ``sl`` from ``params`` on the windows in ``mask``
    and on those in ``other`` (default: the rest), and the bootstrap standard deviation of their
    difference.

    Args:
        hs: (W, P, P) per-window curvatures; gs: (W, P) gradients; mask, other: (W,) bool.
        strata: (W,) labels; the bootstrap resamples within each (default: one stratum). Why:
            which time slots a side holds is fixed by the design, not by the noise, so it is held
            (as ``voe.gap.uncertainty`` holds which windows inform a sparse effect); resampled,
            a side spanning slots of different true values would look noisy instead of different.
        spread: the sd is widened this many times (``voe.gap.parametric.SPREAD``, the one
            measured factor by which resampled windows understate the estimator's spread).
    Returns:
        (estimate on ``mask``, estimate on the rest, widened sd of the difference), each (p,); None if a
        side has fewer than two windows or does not inform a parameter (cost curvature below 1
        per ``scale`` step, as ``voe.gap.uncertainty`` calls a parameter blind).
    """
    h, g = hs[:, sl, sl], gs[:, sl]
    sides = [np.flatnonzero(mask), np.flatnonzero(~mask if other is None else other)]
    if min(len(s) for s in sides) < MIN_WINDOWS:
        return None
    est, boot, cov = [], [], []
    for idx in sides:
        hh, gg = h[idx], g[idx]
        if scale is not None and np.any(np.diag(hh.sum(axis=0)) * scale**2 < 1.0):
            return None
        ridge = 1e-12 * np.eye(hh.shape[1]) * max(float(np.trace(hh.sum(axis=0))), 1e-300)
        try:
            cov.append(np.linalg.inv(hh.sum(axis=0) + ridge))  # (p, p) the step's covariance, residuals standardised
            est.append(params[sl] - cov[-1] @ gg.sum(axis=0))
            lab = np.zeros(len(idx), dtype=int) if strata is None else strata[idx]
            draws = np.concatenate([np.flatnonzero(lab == v)[rng.integers(0, int(np.sum(lab == v)),
                                                                          size=(N_BOOT, int(np.sum(lab == v))))]
                                    for v in np.unique(lab)], axis=1)  # (N, n): positions in ``idx``
            boot.append(np.stack([params[sl] - np.linalg.solve(hh[d].sum(axis=0) + ridge, gg[d].sum(axis=0))
                                  for d in draws]))  # (N, p)
        except np.linalg.LinAlgError:
            return None
    sd = np.maximum(np.std(boot[0] - boot[1], axis=0), np.sqrt(np.diag(cov[0] + cov[1])))
    return est[0], est[1], spread * sd


def material(a: np.ndarray, b: np.ndarray, nominal: np.ndarray) -> np.ndarray:
    """(p,) whether two estimates of a part's parameters differ by at least ``MATERIAL`` of the
    part's strength: the larger of the two sides' distances from the nominal values, over every
    parameter that has one (a constant acceleration's strength is the length of its vector, so a
    near-zero component is not held to a floor of its own size); True where a parameter has no
    nominal value."""
    has = np.isfinite(nominal)
    if not has.any():
        return np.ones(len(a), dtype=bool)
    strength = max(float(np.linalg.norm((a - nominal)[has])), float(np.linalg.norm((b - nominal)[has])))
    return np.where(has, np.abs(a - b) >= MATERIAL * strength, True)


def drifts(shooter: Shooter, sigma: np.ndarray, windows: list[Window], effect: Effect, params: np.ndarray,
           ctx: FitContext, f_scale: float = 3.0, seed: int = 0, stride: float = 0.25) -> list[Drift]:
    """Parts of ``effect`` (at ``params``) that drift.

    ``windows`` start every ``stride`` seconds; windows whose midpoints fall in the same
    ``SLOT`` of episode time form one subsample, each compared with all other windows.
    """
    kept, terms = [], []
    # each window's start velocity profiled out (voe.gap.nuisance); not on scenes with joints,
    # where one body's velocity cannot be stepped alone
    prof = None if shooter.scene.joints else profiled_terms(shooter, sigma, windows, effect, params, ctx, f_scale)
    for i, w in enumerate(windows):  # per window, so each term keeps its window's time
        if prof is not None:  # start velocity profiled out (voe.gap.nuisance)
            t = prof[i]
        else:
            h, g, _ = window_terms(shooter, sigma, [w], effect, params, ctx, f_scale)
            t = (h[0], g[0]) if len(h) else None
        if t is not None:
            kept.append(w)
            terms.append(t)
    if len(kept) < 4:
        return []
    hs, gs = np.stack([t[0] for t in terms]), np.stack([t[1] for t in terms])  # (W, P, P), (W, P)
    eps = shooter.episodes
    mid = np.array([0.5 * (eps[w.ep].t[w.k0] + eps[w.ep].t[w.k1]) - eps[w.ep].t[0] for w in kept])  # (W,)
    slot = np.round(mid / SLOT).astype(int)  # windows at about the same time within their episodes
    splits = {f"time {a * SLOT:.1f} s": (slot == a, slot != a) for a in np.unique(slot)}
    rng = np.random.default_rng(seed)
    scale = effect.scale(ctx)
    parts = effect.parts if isinstance(effect, EffectSum) else (effect,)
    n_tests = len(splits) * effect.n_params
    out, i = [], 0
    for k, e in enumerate(parts):
        sl = slice(i, i + e.n_params)
        i += e.n_params
        nom = e.nominal(ctx)  # (p,)
        worst = None
        for name, (mask, other) in splits.items():
            r = split_estimates(hs, gs, params, mask, sl, rng, other, scale[sl], slot)
            if r is None:
                continue
            a, b, sd = r
            z = np.abs(a - b) / np.maximum(sd, 1e-300)
            df = min(int(mask.sum()), int(other.sum())) - 1  # the smaller side's windows, less one
            for j in np.flatnonzero((z > critical(df, n_tests)) & material(a, b, nom)):
                if worst is None or z[j] > worst.z:
                    worst = Drift(k, e.param_names[j], name, float(a[j]), float(b[j]), float(z[j]))
        if worst is not None:
            out.append(worst)
    return out


def drift_found(p: Problem, model: FitResult, config: GapConfig, seed: int,
                ctx: FitContext | None = None) -> list[Drift]:
    """The parts of ``model`` that drift: its parameters on the windows of one time slot against
    the others (``drifts``), and the parts that push bodies in flight when the flight residual
    changes in time (``voe.gap.drift_flight.flight_drift``). ``ctx``: the fitting episodes'
    context, if the caller has it."""
    ctx = fit_context(p) if ctx is None else ctx
    length = config.fit_window / 2
    stride = length / 2
    windows = make_windows(p.episodes, list(p.split.fit), length, stride=stride, bad_start=p.bad)
    found = drifts(p.shooter, p.sigma, windows, model.effect, model.params, ctx, config.fit.f_scale, seed, stride)
    # the fitting episodes' flight samples with the frames their smoothing averages, so the
    # effect is smoothed as the recording was (``voe.gap.prefit.seen_missing``)
    seen = flight_samples(p.scene, [p.episodes[i] for i in p.split.fit], around=True)
    fl = flight_drift(seen, model.effect, model.params, p.scene, ctx)
    if fl is not None:  # the parts that push bodies in flight took up a force that changes in time
        done = {d.part for d in found}
        moving = flight_movers(ctx.flight, model.effect, model.params, p.scene, ctx)
        found += [replace(fl, part=k) for k in moving if k not in done]
    return found


class DriftAhead:
    """``drift_found`` of the search's model, started in a forked process while the check runs
    (``voe.gap.parallel.Ahead``; with ``n_jobs`` 1 nothing runs ahead).

    Why: the drift test needs only the model, and the check keeps the search's model unless it
    drops a part; the two used to run one after the other in the main process while the fitting
    workers sat idle (about 1 s each of ``bench/gap_speed.py``). ``found`` gives the result only
    for the same effect and parameters to the bit, else None (the caller computes it again), so
    the answer does not depend on ``n_jobs``; the rollouts the forked process simulated are added
    to the data shooter's count, as if simulated here.
    """

    def __init__(self, p: Problem, model: FitResult | None, config: GapConfig, seed: int, n_jobs: int,
                 started: Ahead | None = None) -> None:
        """``started``: ``drift_found`` of this same model, already running (``voe.gap.speculate``)."""
        self.key = None if model is None else _model_key(model)
        self.ahead = None if model is None else started if started is not None else \
            Ahead(lambda: drift_found(p, model, config, seed), n_jobs, (p.shooter,))

    def found(self, model: FitResult) -> list[Drift] | None:
        """The drifting parts of ``model`` if it is the model started ahead, else None."""
        if self.ahead is None:
            return None
        if _model_key(model) != self.key:
            self.ahead.cancel()
            return None
        return self.ahead.result()

    def __enter__(self) -> DriftAhead:
        return self

    def __exit__(self, *exc: object) -> None:
        if self.ahead is not None:
            self.ahead.__exit__(*exc)


def _model_key(model: FitResult) -> tuple:
    """What ``drift_found`` reads of a model: its effect and its parameters, to the bit."""
    return effect_key(model.effect), model.params.tobytes()


def drift_step(p: Problem, loc: Location, s: Search, c: Checked, config: GapConfig, seed: int,
               ahead: DriftAhead | None = None) -> Checked:
    """``c`` without the parts that drift (the rest refitted, bounded and tested again).

    What is left after a drop is refitted and asked again, until nothing drifts. Why: of two
    parts fitted to one force that changes in time, one can take up the change and the other
    the mean; only the first drifts, and once it is dropped the refitted other takes up the
    change in its place. Development case 4446145 (a gust, out of the library): the search
    named ``linear_drag`` + ``constant_acceleration``; the constant drifted (ax -0.272 in the
    windows centred 0.2 s against 0.084, z = 6.1) and was dropped, and ``linear_drag`` alone,
    refitted (c = 0.106), was reported although its own flight residual then changed in time
    (y: -0.243 m/s^2 in the slot at 0.25 s against -0.045, t = 4.0).

    Args:
        ahead: ``drift_found`` of the search's model, started while the check ran; used only if
            the check kept that model.
    """
    model, keys, dropped = c.model, list(c.keys), list(c.dropped)
    if model is None:  # a drift test started ahead is stopped when the caller's ``with`` ends
        return c
    ctx = fit_context(p)
    lo, hi = c.lower, c.upper
    found = ahead.found(model) if ahead is not None else None
    if found is None:
        found = drift_found(p, model, config, seed, ctx)
    if not found:
        return c
    while found:  # what is left, refitted, is asked again (``drift_step``)
        for d in sorted(found, key=lambda d: -d.part):  # from the last part, so indices stay valid
            dropped.append({"effect": keys[d.part], "reason": d.reason(), "drift": {
                "param": d.param, "split": d.split, "early": d.early, "late": d.late, "z": d.z}})
            eff, starts = without(model, d.part)
            keys = keys[:d.part] + keys[d.part + 1:]
            model = None if eff is None else as_sum(s.fitter.refit(eff, starts, s.fitter.config.refine_nfev))
        found = [] if model is None else drift_found(p, model, config, seed, ctx)
    if model is not None:
        lo, hi = model_intervals(p, p.split.fit, model, ctx, config, seed)
        if not all(established(model.effect, lo, hi, ctx)):  # what is left must still be established
            for k in reversed(range(len(keys))):
                dropped.append({"effect": keys[k], "reason": "left without a drifting effect, it is not established"})
            model, keys = None, []
    if model is None:
        lo = hi = np.zeros(0)
    ver, note = verify_on_test(p, model, config, loc.z_threshold)
    nominal = model.effect.nominal(ctx) if model is not None else np.zeros(0)
    return replace(c, model=model, keys=tuple(keys), lower=lo, upper=hi, dropped=tuple(dropped), verification=ver,
                   test_note=note, nominal=nominal)
