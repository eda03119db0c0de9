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
N_BOOT = 400


def gain_lower_bound(before_sse: np.ndarray, after_sse: np.ndarray | None, seed: int = 0) -> float:
    """5th percentile of the held-out gain under a paired bootstrap over held-out windows.

    Why: with few held-out windows one lucky window can carry a spurious gain; requiring the
    gain to stay positive when windows are resampled guards against that.
    """
    if after_sse is None or before_sse.size == 0:
        return 0.0
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, before_sse.size, size=(N_BOOT, before_sse.size))  # (N_BOOT, W)
    gains = 1.0 - np.sqrt(after_sse[idx].sum(axis=1) / np.maximum(before_sse[idx].sum(axis=1), 1e-300))
    return float(np.quantile(gains, 0.05))


@dataclass
class Round:
    """One greedy round: RMSE before, every candidate's result and the winner (if accepted)."""

    before: float
    results: dict[str, FitResult]
    gains: dict[str, float]
    winner: str | None = None
    group: list[str] = field(default_factory=list)
    lower: dict[str, float] = field(default_factory=dict)


def candidate_gains(fitter: Fitter, candidates: dict[str, Effect], current: Effect | None,
                    params: np.ndarray, before: float,
                    progress: Callable[[str], None] | None = None) -> tuple[dict[str, FitResult], dict[str, float]]:
    """Fit ``current + c`` for every candidate; gain = 1 - heldout_after / before."""
    results, gains = {}, {}
    for key, cand in candidates.items():
        effect, starts = extend(current, params, cand, fitter.ctx)
        res = fitter.fit(effect, starts)
        results[key] = res
        ok = before > 0 and np.isfinite(res.heldout_rmse)  # a rollout that blew up is a failed fit
        gains[key] = 1.0 - res.heldout_rmse / before if ok else -np.inf
        if progress:
            progress(key)
    return results, gains


def choose(gains: dict[str, float], results: dict[str, FitResult], candidates: dict[str, Effect],
           contexts: set[str], threshold: float, lower: dict[str, float] | None = None) -> tuple[str | None, list[str]]:
    """Winner and its indistinguishable group among candidates whose gain beats ``threshold``
    and whose bootstrap lower bound ``lower`` is positive; (None, []) if there are none."""
    if not gains:
        return None, []
    lower = lower or {}
    eligible = {k: g for k, g in gains.items() if g > threshold and lower.get(k, 1.0) > 0}
    if not eligible:
        return None, []
    best = max(eligible, key=lambda k: eligible[k])
    floor = results[best].heldout_rmse
    group = [k for k in eligible if results[k].heldout_rmse <= floor * (1 + GROUP_TOL)]

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
    before_sse = fitter.heldout_sse(None, None)
    rounds: list[Round] = []
    pool = dict(candidates)
    for _ in range(max_effects):
        results, gains = candidate_gains(fitter, pool, current, params, before, progress)
        lower = {k: gain_lower_bound(before_sse, r.window_sse) for k, r in results.items()}
        winner, group = choose(gains, results, pool, contexts, threshold, lower)
        rounds.append(Round(before, results, gains, winner, group, lower))
        if winner is None:
            break
        res = fitter.fit(results[winner].effect, [results[winner].params], fitter.config.refine_nfev)
        if res.heldout_rmse > results[winner].heldout_rmse:
            res = results[winner]
        results[winner] = res
        current, params, before, before_sse = res.effect, res.params, res.heldout_rmse, res.window_sse
        for k in group:  # members of the winner's group explain the same thing
            pool.pop(k, None)
        if not pool:
            break
    if current is not None and not isinstance(current, EffectSum):
        current = EffectSum(current.parts)
    return current, params, rounds
