"""Re-selection: once the search has ended with several effects, each part is asked again
whether another candidate of its own round explains the data better with the other parts in.

Why: a round picks its winner on top of the model of the rounds before it, while the effects
of later rounds are still unmodelled, and a flexible candidate can absorb part of an effect
that is not yet in. Development case 9028132 (a constant acceleration (0.257, -0.864) and a spin
damping): round 1 picked the four-parameter ``spring_anchor`` (selection gain 65.8 %) over
``constant_acceleration`` (54.9 %), the spring's anchor bending its pull toward what the
damping does; round 2 added ``angular_damping``. With the damping in, the constant in the
spring's place gains 71.0 % over the spring model on the selection windows (its 5 % bootstrap
quantile 54.6 %), at (0.236, -0.902). A greedy search never revisits a round; this asks each
round's question again, once, with the answer of the later rounds known (a backward step of
stepwise selection).

The swaps are independent refits, so they run in the finder's ``n_jobs`` processes: every part's
swaps against the search's model at once, and a later part's again only after an earlier part
was replaced (the model they were asked against changed). Each swap is deterministic, so the
answer does not depend on ``n_jobs``. Why: asked one after the other they cost ``bench/gap_speed.py``
49 s of its 89 s (15 swaps of 3.3 s, after the half-step restart lowered the speed case's round
threshold to the 5 % floor).

Asked are the candidates that passed their round alone (gain above that round's null
threshold) and those whose fit *lost* as much (gain below minus the threshold): the nominal
value lies inside every candidate's bounds, so a fit that predicts the selection windows far
worse than the nominal model was pulled by the fitting windows toward something they reject,
typically an effect not yet modelled. Development case 9028134 (a linear drag 0.267 1/s and a
restitution): round 1 fitted ``linear_drag`` at 0.79 (the drag dissipating the energy the
unmodelled restitution takes at bounces; selection gain -81 %, at the true 0.267 it would gain
90 %) and named ``quadratic_drag`` (36.6 %); with the restitution in, the linear drag in its place
gains 76.0 % over the model (quantile 66.3 %), at 0.266, and the spring the search had added
third is then dropped by the check. A candidate takes the place only if it
gains more than the round's threshold over the whole model, with a positive bootstrap lower
bound: the evidence the round demanded of its winner, now against the winner itself.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter, without
from voe.gap.mass_ratio import not_offered
from voe.gap.search import Round, counted_map, gain_lower_bound, window_gain


def swapped(fitter: FoldedFitter, model: FitResult, k: int, cand: FitResult) -> FitResult:
    """``model`` with part ``k`` replaced by the last part of ``cand`` (a round's candidate fit),
    fitted as any candidate is on top of the other parts (its starts from a regression on what
    they leave unexplained, ``voe.gap.fit.extend``), refined, and put back at place ``k``.

    Why not refit from the candidate's own fit of its round: that fit is what the missing effect
    pulled off (9028134: the linear drag at 0.79, truth 0.267), and a refit from there with the
    model's other parameters ended at 0 (selection gain -307 %); fitted as a candidate on top of
    the restitution it gains 76.0 %, at 0.266.
    """
    eff, starts = without(model, k)
    rest = FitResult(eff, starts[0], 0.0, 0.0, None, starts)  # the other parts, at the model's values
    first = fitter.fit_candidate(rest, cand.effect.parts[-1])
    ref = fitter.refine(first)
    res = ref if window_gain(model.window_sse, ref.window_sse) >= window_gain(model.window_sse, first.window_sse) \
        else first
    parts = list(res.effect.parts)
    order = list(range(len(parts) - 1))
    order.insert(k, len(parts) - 1)  # the new part back at place k

    def moved(p: np.ndarray) -> np.ndarray:
        split = EffectSum(tuple(parts)).split(p)
        return np.concatenate([split[j] for j in order])

    return replace(res, effect=EffectSum(tuple(parts[j] for j in order)), params=moved(res.params),
                   fold_params=tuple(moved(p) for p in res.fold_params))


def _alternatives(rnd: Round, keys: list[str], fitter: FoldedFitter, model: FitResult, k: int) -> list[str]:
    """The round's candidates asked in place ``k`` (its winner's) of ``model``: those that passed
    alone, or whose fit lost as much (see the module), best first; not one that would put a mass on
    every body (``voe.gap.mass_ratio``)."""
    rest = tuple(e for j, e in enumerate(model.effect.parts) if j != k)
    return sorted((c for c, g in rnd.gains.items()
                   if c not in keys and c in rnd.results and np.isfinite(g) and abs(g) > rnd.threshold
                   and not not_offered(fitter, rest + rnd.results[c].effect.parts[-1:])),
                  key=lambda c: -rnd.gains[c])


def _swaps(fitter: FoldedFitter, model: FitResult, asks: list[tuple[int, Round, str]],
           n_jobs: int) -> dict[tuple[int, str], FitResult]:
    """``swapped`` for each (part, round, candidate), in ``n_jobs`` forked processes
    (``voe.gap.search.counted_map``)."""
    res = counted_map(fitter, lambda a: swapped(fitter, model, a[0], a[1].results[a[2]]), asks, n_jobs)
    return {(k, c): r for (k, _, c), r in zip(asks, res, strict=True)}


def reselect(fitter: FoldedFitter, model: FitResult | None, keys: list[str], rounds: list[Round],
             q: float, fixed: set[str] = frozenset(), n_jobs: int = 1) -> tuple[FitResult | None, list[str], bool]:
    """Ask each part of a model of two or more parts again (see the module). Returns the model,
    its keys (in part order) and whether anything changed; ``rounds`` is updated in place (the
    round of a replaced part names its new winner and says why).

    ``fixed``: parts not asked again, those a pair step accepted (together, because no single
    candidate passed their round on its own; a candidate that did was a trial the next round
    refused, ``voe.gap.greedy.Trial``, and is not brought back here). ``n_jobs``: processes for
    the swaps (the answer does not depend on it)."""
    if model is None or len(keys) < 2:
        return model, keys, False
    changed = False
    parts = _asked(rounds, keys, fixed)  # (part, its round's index); later swaps leave these as they are
    swaps: dict[tuple[int, str], FitResult] = {}
    for k, at in parts:
        key, rnd = keys[k], rounds[at]
        alts = _alternatives(rnd, keys, fitter, model, k)
        if any((k, c) not in swaps for c in alts):  # not yet asked against this model: this part's
            swaps = _swaps(fitter, model, [(j, rounds[a], c) for j, a in parts if j >= k  # and every later part's
                                           for c in _alternatives(rounds[a], keys, fitter, model, j)],
                           n_jobs)  # swaps at once
        best: tuple[float, float, str, FitResult] | None = None
        for c in alts:
            res = swaps[k, c]
            g = window_gain(model.window_sse, res.window_sse)
            lo = gain_lower_bound(model.window_sse, res.window_sse, q=q)
            if g > rnd.threshold and lo > 0 and (best is None or g > best[0]):
                best = (g, lo, c, res)
        if best is None:
            continue
        g, lo, c, res = best
        others = " + ".join(x for x in keys if x != key)
        rounds[at] = replace(rnd, winner=c, group=(c, key) + tuple(x for x in rnd.group if x not in (c, key)),
                             tie=None, basis=f"{rnd.basis}; re-selected after the search: with {others} in, {c} in "
                                         f"place of {key} gains {100 * g:.1f} % on the selection windows (its "
                                         f"{100 * q:.0f} % bootstrap quantile {100 * lo:.1f} %, threshold "
                                         f"{100 * rnd.threshold:.1f} %)")
        model, keys, changed = res, keys[:k] + [c] + keys[k + 1:], True
        swaps = {}  # asked against the model before this swap
    return model, keys, changed


def _asked(rounds: list[Round], keys: list[str], fixed: set[str]) -> list[tuple[int, int]]:
    """(place, index of its round) of each part asked again: one its own round named, with a
    threshold, and not ``fixed``."""
    out = []
    for k, key in enumerate(keys):
        at = next((i for i, r in enumerate(rounds) if r.winner == key), None)
        if at is not None and rounds[at].threshold is not None and key not in fixed:
            out.append((k, at))
    return out
