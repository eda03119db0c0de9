"""A region winner's unlimited form at the region's own strength.

Why: a region effect is its global effect plus two edges, so when a round's winner is a region
and its global form fitted worse, the question is whether the data need the edges or whether the
global fit merely went astray. On fitting windows whose outcome flips with a small change (a
collision after a roll) the global fit's cost is jagged along its parameter, and the fit can
stop on the wrong side of a jump while the region, by leaving those windows' place out of its
interval, fits the rest. Development case 2250050 (a global ``rolling_resistance``, c = 0.0825;
``docs/bench-runs/dev-s50``): one of eight fitting windows cost 1036 at c = 0.053 and 60323 at
the truth, so the global fit stopped at 0.053 and gained 11.1 % on the selection windows, while
``rolling_resistance_region`` (c = 0.084 over x 2.12..5.26 m) gained 29.0 % and was named. The
global form at the region's strength, c = 0.084 everywhere, gains 26.5 %: the edges bought
nothing the selection windows can see. ``global_at_region`` gives that point as a result of the
global form (its parameters ``Effect.unlimited`` of the region's, every other part's as the
region's fit left them), and ``voe.gap.greedy`` lets it stand for the global form in the round's
group when it predicts better than the global's own fit; the round's existing rule
(``voe.gap.search.tie_keeps_global``) then decides, so a real patch, where the global form at the
patch's strength predicts worse off the patch, keeps its name.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter
from voe.gap.search import GROUP_TOL, TieBreak, tie_break, tie_keeps_global, window_gain


def global_at_region(fitter: FoldedFitter, region: FitResult, plain: FitResult) -> FitResult | None:
    """``plain``'s effect (the region's global form, after the same earlier parts) with every
    fold's parameters taken from ``region``'s fit: the earlier parts' as they are, the newest
    part's ``unlimited`` (clipped to the global part's bounds); None when the region has no such
    form or the two effects differ in their earlier parts.

    The result's selection errors (``window_sse``) are evaluated (one rollout of each fold's
    selection windows); it is not fitted, and its ``train_cost`` is NaN until ``with_cost``.
    """
    part: Effect = region.effect.parts[-1]
    glob: Effect = plain.effect.parts[-1]
    if [p.name for p in region.effect.parts[:-1]] != [p.name for p in plain.effect.parts[:-1]]:
        return None
    n = part.n_params
    fold_params = []
    for f, p in zip(fitter.folds, region.fold_params, strict=True):
        g = part.unlimited(p[-n:], f.ctx)
        if g is None:
            return None
        lo, hi = glob.bounds(f.ctx)
        fold_params.append(np.concatenate([p[:-n], np.clip(g, lo, hi)]))
    fold_params = tuple(fold_params)
    sse = fitter.heldout_sse(plain.effect, fold_params)  # (W,)
    n_test = sum(f._n_test for f in fitter.folds)
    return FitResult(plain.effect, np.median(np.stack(fold_params), axis=0), float("nan"),
                     float(np.sqrt(np.sum(sse) / max(n_test, 1))), sse, fold_params)


def with_cost(fitter: FoldedFitter, res: FitResult) -> FitResult:
    """``res`` with its training cost over every fold (one rollout of the training windows): asked
    only of a point that joins its group, whose result the round records."""
    cost = float(sum(f.cost(res.effect, p) for f, p in zip(fitter.folds, res.fold_params, strict=True)))
    return replace(res, train_cost=cost)


def unlimited_member(fitter: FoldedFitter, winner: str, results: dict[str, FitResult], gains: dict[str, float],
                     candidates: dict[str, Effect], contexts: set[str] | Callable[[], set[str]], noise: float,
                     before_sse: np.ndarray) -> tuple[FitResult, float, TieBreak | None, str] | None:
    """The region winner's global form at the region's strength, if it joins the winner's group:
    (its result, its gain, the tie between the two, why), else None.

    It joins when it predicts the selection windows better than the global form's own fit, within
    ``GROUP_TOL`` of the winner's error (the group's rule), and the two stay indistinguishable on
    the windows where their predictions differ (``tie_keeps_global`` on their ``tie_break``).
    """
    plain = candidates[winner].global_name
    via = global_at_region(fitter, results[winner], results[plain])
    if via is None:
        return None
    g = window_gain(before_sse, via.window_sse)
    if not (g > gains[plain] and 1.0 - g <= (1.0 - gains[winner]) * (1 + GROUP_TOL)):
        return None
    _, kept, basis, tie = tie_break(fitter, [winner, plain], {**results, plain: via}, candidates,
                                    contexts() if callable(contexts) else contexts, {**gains, plain: g}, noise)
    if not tie_keeps_global(winner, kept, tie, candidates):
        return None
    return with_cost(fitter, via), g, tie, (f"{plain} at {winner}'s strength, everywhere, gains {100 * g:.1f} % (its own fit "
                         f"{100 * gains[plain]:.1f} %; {basis})")
