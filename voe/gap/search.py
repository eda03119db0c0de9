"""Greedy search over candidate effects with a null-calibrated acceptance threshold.

Why: adding any flexible term lowers the training error, so an effect is accepted only if it
lowers the *held-out* RMSE by more than the threshold the same search reaches on simulated clean
data. Candidates whose held-out fit is as good as the winner's are reported together as a group
the data cannot tell apart, instead of picking one silently; within a group the effect whose
physical context matches the located contexts is named first.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from voe.gap.effects.base import Effect, EffectSum
from voe.gap.fit import FitResult, Fitter, extend

GROUP_TOL = 0.10  # held-out RMSE within 10 % of the winner's counts as indistinguishable


@dataclass
class Round:
    """One greedy round: RMSE before, every candidate's result and the winner (if accepted)."""

    before: float
    results: dict[str, FitResult]
    gains: dict[str, float]
    winner: str | None = None
    group: list[str] = field(default_factory=list)


def candidate_gains(fitter: Fitter, candidates: dict[str, Effect], current: Effect | None,
                    params: np.ndarray, before: float,
                    progress: Callable[[str], None] | None = None) -> tuple[dict[str, FitResult], dict[str, float]]:
    """Fit ``current + c`` for every candidate; gain = 1 - heldout_after / before."""
    results, gains = {}, {}
    for key, cand in candidates.items():
        effect, starts = extend(current, params, cand, fitter.ctx)
        res = fitter.fit(effect, starts)
        results[key] = res
        gains[key] = 1.0 - res.heldout_rmse / before if before > 0 else 0.0
        if progress:
            progress(key)
    return results, gains


def choose(gains: dict[str, float], results: dict[str, FitResult], candidates: dict[str, Effect],
           contexts: set[str], threshold: float) -> tuple[str | None, list[str]]:
    """Winner and its indistinguishable group, or (None, []) if no gain beats ``threshold``."""
    if not gains:
        return None, []
    best = max(gains, key=lambda k: gains[k])
    if gains[best] <= threshold:
        return None, []
    floor = results[best].heldout_rmse
    group = [k for k in gains if gains[k] > threshold and results[k].heldout_rmse <= floor * (1 + GROUP_TOL)]

    def rank(k: str) -> tuple[int, float]:
        ctx_match = any(c in contexts for c in candidates[k].contexts)
        return (0 if ctx_match else 1, results[k].heldout_rmse)

    group.sort(key=rank)
    return group[0], group


def greedy(fitter: Fitter, candidates: dict[str, Effect], threshold: float, max_effects: int,
           contexts: set[str], progress: Callable[[str], None] | None = None) -> tuple[Effect | None, np.ndarray, list[Round]]:
    """Add effects one at a time while the held-out gain beats ``threshold``.

    Returns:
        The accepted effect (an ``EffectSum`` or None), its parameters and the rounds.
    """
    current: Effect | None = None
    params = np.zeros(0)
    before = fitter.heldout(None, None)
    rounds: list[Round] = []
    pool = dict(candidates)
    for _ in range(max_effects):
        results, gains = candidate_gains(fitter, pool, current, params, before, progress)
        winner, group = choose(gains, results, pool, contexts, threshold)
        rounds.append(Round(before, results, gains, winner, group))
        if winner is None:
            break
        res = fitter.fit(results[winner].effect, [results[winner].params], fitter.config.refine_nfev)
        if res.heldout_rmse > results[winner].heldout_rmse:
            res = results[winner]
        results[winner] = res
        current, params, before = res.effect, res.params, res.heldout_rmse
        for k in group:  # members of the winner's group explain the same thing
            pool.pop(k, None)
        if not pool:
            break
    if current is not None and not isinstance(current, EffectSum):
        current = EffectSum(current.parts)
    return current, params, rounds
