"""The pair step: when no single candidate passes a round, fit the most promising pairs jointly.

Why: with two effects at once, each alone can make the selection error *worse*, while the two
together remove it. Development case 3629061 (a wind and a spin damping): fitted alone,
``constant_acceleration`` came out near the truth (-0.46, -0.31 against -0.57, -0.29 m/s^2) and
``angular_damping`` too (0.0132 against 0.0121), yet their selection gains were -23 % and -55 %:
a ball with the right wind but the wrong spin, or the right spin but no wind, meets the box and
the floor elsewhere than recorded, and every collision after that is off. No greedy order
can add them one at a time. Which pairs to try is decided by the *training* cost (the fitted
parameters explain the fitting windows), not by the selection gain that failed: ranked by gain,
the pair would have been two drags.

The threshold is calibrated the same way as a round's (``voe.gap.null``): the identical pair
step runs on the null's clean replicate (same top-``PAIR_TOP`` rule, same joint fits), and a
data pair is accepted only if its gain beats the round's single threshold, the null's best pair
gain and the null pair's bootstrap ``1 - alpha`` quantile, with a positive bootstrap lower bound.
Each part must then still earn its place (``voe.gap.check`` refits without it).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter
from voe.gap.null import NullSearch
from voe.gap.search import Round, counted_map, gain_lower_bound, null_threshold, window_gain

PAIR_TOP = 3  # candidates of lowest training cost whose pairs are fitted (3 pairs)


@dataclass(frozen=True)
class NullSnapshot:
    """The null search as it stood at one round (what ``pair_step`` reads of a ``NullSearch``),
    with that round's candidate fits ``results``: kept so the pair step can be run on an earlier
    round after the null has moved on (``voe.gap.greedy``, an undone trial)."""

    fitter: FoldedFitter
    current: FitResult | None
    before_sse: np.ndarray  # (W,) the null's selection errors before that round
    alpha: float
    seed: int
    results: dict[str, FitResult]


@dataclass(frozen=True)
class Pair:
    """The best jointly fitted pair of a round: its keys (lower training cost first), fit and gain."""

    keys: tuple[str, str]
    result: FitResult
    gain: float


def _train_cost(fitter: FoldedFitter, res: FitResult) -> float:
    """Training cost of ``res`` on every fold's full training windows (a sparse effect's own fit
    cost counts only the windows it was focused on, so its cost is recomputed alike).

    A fit that ended on the full training windows (``FitResult.train_full``) already holds that
    number: the cost of its final parameters, summed over folds in the same order, to the bit.
    Why reuse it: the fits ran in forked workers, so recomputing it here simulated every
    candidate's training windows again in the main process while both workers waited (on
    ``bench/gap_speed.py``'s case 96 rollouts before the pair step's fits could start).
    """
    if res.train_full:
        return float(res.train_cost)
    return float(sum(f.cost(res.effect, p) for f, p in zip(fitter.folds, res.fold_params, strict=True)))


def best_pair(fitter: FoldedFitter, results: dict[str, FitResult], current: FitResult | None,
              before_sse: np.ndarray, top: int = PAIR_TOP, n_jobs: int = 1) -> Pair | None:
    """Fit the pairs of the ``top`` candidates of lowest training cost jointly (each from the two
    singles' fitted parameters, every fold its own, in ``n_jobs`` processes); the pair of
    highest selection gain (each fit deterministic: the answer does not depend on ``n_jobs``)."""
    n_cur = 0 if current is None else current.params.size
    costs = {k: _train_cost(fitter, r) for k, r in results.items() if np.all(np.isfinite(r.params))}
    ranked = distinct(fitter, results, current, at_limits(fitter, results, sorted(
        (k for k in costs if np.isfinite(costs[k])), key=lambda k: costs[k])), top)
    best: Pair | None = None
    pairs = list(combinations(ranked, 2))

    def fit(ab: tuple[str, str]) -> FitResult:
        ra, rb = results[ab[0]], results[ab[1]]
        parts = ra.effect.parts + (rb.effect.parts[-1],)
        starts = tuple(np.concatenate([pa, pb[n_cur:]]) for pa, pb in zip(ra.fold_params, rb.fold_params, strict=True))
        return fitter.refit(EffectSum(parts), starts)

    for (a, b), res in zip(pairs, counted_map(fitter, fit, pairs, n_jobs), strict=True):
        gain = window_gain(before_sse, res.window_sse)
        if np.isfinite(gain) and (best is None or gain > best.gain):
            best = Pair((a, b), res, float(gain))
    return best


def at_limits(fitter: FoldedFitter, results: dict[str, FitResult], ranked: list[str]) -> list[str]:
    """``ranked`` with each candidate whose fit sits at the bound where it becomes its nested limit
    (``Effect.at_limit`` in every fold) replaced there by that limit, if the limit is ranked too
    (each key once, at its first place).

    Why: a point attractor or a spring whose point runs to its search bound was heading for a
    constant force (``constant_acceleration``), and its position says where the bound lies, not
    where a point is; ``voe.gap.search.bound_limit`` names the limit for a single winner, and the
    pair step must pair the limit for the same reason. Development case 5250116 (a wind and a
    spin damping, fitted on top of a first-round drag): the training costs ranked
    ``angular_damping``, ``spring_anchor``, ``point_attractor`` (its point at the y bound,
    -2.30 m) and then ``constant_acceleration`` (1.5 % more cost), so only the attractor was paired with
    the spin damping (selection gain 70.5 %) and was named; the spin damping with the constant
    acceleration gains 70.8 % at about half the training cost, and was never fitted.
    """
    out: list[str] = []
    for k in ranked:
        part = results[k].effect.parts[-1]
        lim = next((j for j in ranked if results[j].effect.parts[-1].name == part.limit_name), None) \
            if part.limit_name else None
        n, fps = part.n_params, results[k].fold_params
        if lim is not None and len(fps) == len(fitter.folds) and all(
                part.at_limit(p[-n:], f.ctx) for f, p in zip(fitter.folds, fps, strict=True)):
            k = lim
        if k not in out:
            out.append(k)
    return out


REDUNDANT = 0.5  # two fits whose training predictions differ by less than half of what either changes


def _train_residuals(fitter: FoldedFitter, effect, fold_params) -> np.ndarray:
    """Every fold's training residuals at ``fold_params``, flattened (non-finite set to 0)."""
    return np.nan_to_num(np.concatenate([
        np.concatenate([r.ravel() for r in f.shooter.residuals(f.train, effect, None if fold_params is None else p)])
        for f, p in zip(fitter.folds, fold_params or (None,) * len(fitter.folds), strict=True)]))


def distinct(fitter: FoldedFitter, results: dict[str, FitResult], current: FitResult | None, ranked: list[str],
             top: int) -> list[str]:
    """The first ``top`` of ``ranked`` (by training cost) that explain different motion.

    Two fits are redundant when their training predictions differ by less than ``REDUNDANT``
    times the smaller of their changes from ``current``; of redundant candidates the one with
    fewer parameters stays (it explains the same motion more simply). Why: on development case
    3629057 (a wind and a spin damping, seed 3629) the three lowest training costs were
    ``point_attractor``, ``spring_anchor`` (its anchor 10 m away) and ``constant_acceleration``,
    three models of the wind, whose predictions differed by 0.09-0.35 of their changes, while
    every other pair differed by 1.7 or more; ``angular_damping`` was never paired.
    """
    base = _train_residuals(fitter, None if current is None else current.effect,
                            None if current is None else current.fold_params)
    kept: list[tuple[str, np.ndarray]] = []
    for k in ranked:
        if len(kept) >= top:
            break
        rk = _train_residuals(fitter, results[k].effect, results[k].fold_params)
        ck = float(np.linalg.norm(rk - base))
        for i, (j, rj) in enumerate(kept):
            cj = float(np.linalg.norm(rj - base))
            if np.linalg.norm(rk - rj) < REDUNDANT * min(ck, cj):
                if results[k].effect.parts[-1].n_params < results[j].effect.parts[-1].n_params:
                    kept[i] = (k, rk)
                break
        else:
            kept.append((k, rk))
    return [k for k, _ in kept]


def pair_threshold(null_pair: Pair | None, null_before: np.ndarray, single: float, alpha: float,
                   seed: int = 0) -> float:
    """The pair step's threshold: the round's single threshold, the null's best pair gain and its
    bootstrap ``1 - alpha`` quantile, whichever is largest."""
    if null_pair is None:
        return single
    q, _ = null_threshold(null_before, {"pair": null_pair.result}, alpha, seed)
    return float(max(single, q, null_pair.gain))


@dataclass(frozen=True)
class PairStep:
    """An accepted pair step: the pair, its threshold, and the two rounds it adds to the search
    (the first holds the round's single-candidate results, the second the joint fit)."""

    pair: Pair
    threshold: float
    rounds: tuple[Round, Round]


def data_pair(fitter: FoldedFitter, results: dict[str, FitResult], current: FitResult | None,
              before_sse: np.ndarray, floor: float, q: float, n_jobs: int = 1) -> tuple[Pair, float] | None:
    """The data's best jointly fitted pair and its ``q`` bootstrap lower bound, if its gain is
    above ``floor`` and the bound positive; else None (no threshold of at least ``floor`` can
    accept it). The first half of ``pair_step``: it needs no null, so the greedy loop can ask it
    before deciding whether a round's null is needed at all (``voe.gap.greedy``)."""
    pair = best_pair(fitter, results, current, before_sse, n_jobs=n_jobs)
    if pair is None or pair.gain <= floor:
        return None
    low = gain_lower_bound(before_sse, pair.result.window_sse, q=q)
    return (pair, low) if low > 0 else None


def pair_step(fitter: FoldedFitter, results: dict[str, FitResult], gains: dict[str, float], lower: dict[str, float],
              before: float, current: FitResult | None, before_sse: np.ndarray, null: NullSearch | NullSnapshot,
              null_results: dict[str, FitResult], thr: float, q: float, n_jobs: int = 1,
              found: tuple[Pair, float] | None = None) -> PairStep | None:
    """The data's best jointly fitted pair if it passes its threshold, else None.

    The null's identical pair step (its own round's results, before its forced candidate is
    refined in) is run only when the data's pair beats the single threshold ``thr`` with a
    positive ``q`` bootstrap lower bound: it can only raise the bar, so skipping it otherwise
    changes no answer.

    Args:
        results, gains, lower: the round's single-candidate fits, gains and lower bounds.
        before: the round's selection RMSE before (for its ``Round``).
        found: ``data_pair``'s answer for these results if the caller already has it (with a
            floor not above ``thr``), so the data's pairs are not fitted twice.
    """
    found = data_pair(fitter, results, current, before_sse, thr, q, n_jobs) if found is None else found
    if found is None or found[0].gain <= thr:
        return None
    pair, low = found
    null_pair = best_pair(null.fitter, null_results, null.current, null.before_sse, n_jobs=n_jobs)
    thr_pair = pair_threshold(null_pair, null.before_sse, thr, null.alpha, null.seed)
    if pair.gain <= thr_pair:
        return None
    a, b = pair.keys
    basis = (f"no single candidate passed; {a} and {b} fitted jointly gain {100 * pair.gain:.1f} % "
             f"(pair threshold {100 * thr_pair:.1f} %, from the same pair step on clean data)")
    return PairStep(pair, thr_pair, (Round(before, results, gains, lower, thr_pair, a, (a,), basis),
                                     Round(before, {b: pair.result}, {b: pair.gain}, {b: low}, thr_pair, b, (b,),
                                           f"accepted jointly with {a}")))
