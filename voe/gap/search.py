"""Greedy search over candidate effects, each round's acceptance threshold calibrated by the
identical search on simulated clean data.

Why: adding any flexible term lowers the training error, so an effect is accepted only if it
lowers the *selection* error (episodes the fit never saw) by more than the same search reaches,
in the same round, on data simulated from the nominal scene (``NullSearch``: same candidates,
budget, refine step and selection windows; round 2 is calibrated on what a second effect gains
on clean data after a first one was forced in). Candidates whose selection error is within 10 %
of the winner's form a group. Within a group the winner is the member that predicts best on the
selection windows where the members' predictions differ (an impact-only effect and an
always-on drag differ in windows without an impact), not the one whose context words match; the
context decides only when no window tells them apart, and the group is then reported as
indistinguishable. Group members stay candidates in later rounds.

The gain is one minus the geometric mean over selection windows of each window's RMSE ratio
(after / before), not the ratio of pooled RMSEs. Why: a window with a collision whose outcome
flips with any small change carries most of the pooled squared error. Pooled, such a window let
a drag of 0.006 1/s "cut" clean data's error by 15 %; in the geometric mean every window counts
once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter, as_sum
from voe.parallel import parallel_map

GROUP_TOL = 0.10  # selection error ratio within 10 % of the winner's counts as indistinguishable
N_BOOT = 400
LOG_CLIP = 10.0  # a window's log SSE ratio is clipped to +-10 (a blown-up rollout counts, but finitely)


def window_gain(before_sse: np.ndarray, after_sse: np.ndarray | None, idx: np.ndarray | None = None) -> float | np.ndarray:
    """1 - geometric mean over windows of RMSE_after / RMSE_before.

    Args:
        before_sse, after_sse: (W,) per-window sums of squared residuals.
        idx: optional (N, W) bootstrap indices; then an (N,) array of resampled gains.
    """
    if after_sse is None or before_sse.size == 0 or not np.all(np.isfinite(after_sse)):
        return -np.inf if idx is None else np.full(len(idx), -np.inf)
    lr = np.clip(np.log(np.maximum(after_sse, 1e-300) / np.maximum(before_sse, 1e-300)), -LOG_CLIP, LOG_CLIP)  # (W,)
    if idx is None:
        return float(1.0 - np.exp(0.5 * lr.mean()))
    return 1.0 - np.exp(0.5 * lr[idx].mean(axis=1))


def gain_lower_bound(before_sse: np.ndarray, after_sse: np.ndarray | None, seed: int = 0, q: float = 0.05) -> float:
    """``q`` quantile of the gain under a paired bootstrap over selection windows.

    Why: one chaotic window (a collision whose outcome flips with any small change) can carry a
    spurious gain; requiring the gain to stay positive when windows are resampled rejects it.
    """
    if after_sse is None or before_sse.size == 0:
        return 0.0
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, before_sse.size, size=(N_BOOT, before_sse.size))  # (N_BOOT, W)
    return float(np.quantile(window_gain(before_sse, after_sse, idx), q))


def null_threshold(before_sse: np.ndarray, results: dict[str, FitResult], alpha: float = 0.05,
                   seed: int = 0) -> tuple[float, np.ndarray]:
    """(1 - alpha) quantile of the *best* candidate's gain on clean data, bootstrapped.

    Why: on clean data every gain is a false discovery, and the search keeps the best of many
    candidates, so the statistic to calibrate is the maximum over candidates. Each candidate's
    per-window error is resampled jointly, keeping the candidates' correlation.

    Returns:
        The threshold and the (N_BOOT,) bootstrap distribution of the null's best gain.
    """
    sse = [r.window_sse for r in results.values() if r.window_sse is not None and np.all(np.isfinite(r.window_sse))]
    if before_sse.size == 0 or not sse:
        return 0.0, np.zeros(0)
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, before_sse.size, size=(N_BOOT, before_sse.size))  # (N_BOOT, W)
    gains = np.stack([window_gain(before_sse, a, idx) for a in sse])  # (C, N_BOOT)
    best = gains.max(axis=0)
    return float(np.quantile(best, 1.0 - alpha)), best


@dataclass(frozen=True)
class Round:
    """One greedy round: selection RMSE before, every candidate's result, gain and bootstrap lower
    bound, the round's null threshold, and the winner (if accepted) with its group and how the
    group was decided."""

    before: float
    results: dict[str, FitResult]
    gains: dict[str, float]
    lower: dict[str, float]
    threshold: float
    winner: str | None = None
    group: tuple[str, ...] = ()
    basis: str = ""

    def to_dict(self) -> dict:
        return {"before": self.before, "threshold_gain": self.threshold, "winner": self.winner,
                "group": list(self.group), "basis": self.basis,
                "gains": {k: (round(g, 4) if np.isfinite(g) else None) for k, g in self.gains.items()}}


def candidate_gains(fitter: FoldedFitter, candidates: dict[str, Effect], current: FitResult | None,
                    before_sse: np.ndarray, progress: Callable[[str], None] | None = None,
                    n_jobs: int = 1) -> tuple[dict[str, FitResult], dict[str, float]]:
    """Fit ``current + c`` for every candidate; gain = ``window_gain`` against ``before_sse`` (W,).

    With ``n_jobs > 1`` the candidates are fitted in that many forked processes. Why fork: the
    fitter holds pymunk scenes and recordings; forked workers inherit them instead of pickling
    them, and each candidate's fit is deterministic, so the results do not depend on ``n_jobs``.
    """
    results: dict[str, FitResult] = {}
    task = (fitter, candidates, current)
    n0, spent = fitter.shooter.n_rollouts, 0
    for key, res, n_roll in parallel_map(lambda k: _fit_one(k, task), list(candidates), n_jobs, start_method="fork"):
        results[key] = res
        spent += n_roll
        if progress:
            progress(key)
    fitter.shooter.n_rollouts = n0 + spent  # forked workers counted in their own copies
    gains = {k: window_gain(before_sse, r.window_sse) for k, r in results.items()}  # -inf for a rollout that blew up
    return results, gains


def _fit_one(key: str, task: tuple) -> tuple[str, FitResult, int]:
    """Fit candidate ``key`` of ``task``; returns the rollouts it cost."""
    fitter, candidates, current = task
    n0 = fitter.shooter.n_rollouts
    res = fitter.fit_candidate(current, candidates[key])
    return key, res, fitter.shooter.n_rollouts - n0


def context_match(effect_contexts: tuple[str, ...], located: set[str]) -> bool:
    """Whether an effect's contexts name a located context (``region x 0.1..0.5 m`` is ``region``)."""
    words = {c.split()[0] for c in located if c}
    return any(c in words for c in effect_contexts)


def tie_break(fitter: FoldedFitter, group: list[str], results: dict[str, FitResult], candidates: dict[str, Effect],
              contexts: set[str], gains: dict[str, float], noise: float) -> tuple[str, tuple[str, ...], str]:
    """Winner of a group whose selection errors are within ``GROUP_TOL``.

    Members are compared on the selection windows where some pair's predictions differ by more
    than twice the noise floor ``noise`` (m, RMS over the window): the member with the lowest
    mean log error there wins, and members still within ``GROUP_TOL`` of it stay in the
    reported group. Without such windows the data cannot tell them apart, and the member whose
    contexts match the located contexts is named first.
    """
    res = {k: fitter.residuals(results[k].effect, results[k].fold_params) for k in group}
    n_w = len(res[group[0]])
    differ = np.zeros(n_w, dtype=bool)
    for i, a in enumerate(group):
        for b in group[i + 1:]:
            d = np.array([np.sqrt(np.mean((ra - rb) ** 2)) for ra, rb in zip(res[a], res[b], strict=True)])
            differ |= d > 2 * noise
    if differ.sum() >= 2:
        score = {k: float(np.mean([np.log(max(float(np.sum(r**2)), 1e-300)) for r, m in zip(res[k], differ, strict=True)
                                   if m])) for k in group}
        best = min(group, key=lambda k: score[k])
        kept = tuple(sorted((k for k in group if score[k] - score[best] <= 2 * np.log1p(GROUP_TOL)),
                            key=lambda k: score[k]))
        return best, kept, f"chosen on the {int(differ.sum())} selection windows where the group's predictions differ"
    ranked = sorted(group, key=lambda k: (0 if context_match(candidates[k].contexts, contexts) else 1, -gains[k]))
    return ranked[0], tuple(ranked), "predictions differ in no selection window; named by the located context"


def choose(gains: dict[str, float], lower: dict[str, float], threshold: float) -> list[str]:
    """Candidates whose gain beats ``threshold``, whose bootstrap lower bound is positive and
    whose error is within ``GROUP_TOL`` of the best such candidate's (best first); [] if none."""
    eligible = {k: g for k, g in gains.items() if g > threshold and lower.get(k, 1.0) > 0}
    if not eligible:
        return []
    best = max(eligible, key=lambda k: eligible[k])
    floor = 1.0 - eligible[best]  # the winner's geometric-mean error ratio
    return sorted((k for k in eligible if 1.0 - eligible[k] <= floor * (1 + GROUP_TOL)), key=lambda k: -eligible[k])


def accept(fitter: FoldedFitter, res: FitResult, gain: float, before_sse: np.ndarray) -> FitResult:
    """The refine step (a longer fit from the winner's parameters), kept if it does not lose."""
    ref = fitter.refine(res)
    return ref if window_gain(before_sse, ref.window_sse) >= gain else res


@dataclass(frozen=True)
class SearchResult:
    """What the greedy search accepted (``model`` is None when nothing was) and every round."""

    model: FitResult | None
    rounds: tuple[Round, ...]
    keys: tuple[str, ...]  # candidate key of each accepted part, in order

    @property
    def groups(self) -> list[list[str]]:
        return [list(r.group) for r in self.rounds if r.winner]


def greedy(fitter: FoldedFitter, candidates: dict[str, Effect], threshold: Callable[[int], float], max_effects: int,
           contexts: set[str], noise: float, progress: Callable[[str], None] | None = None,
           lower_q: float | None = 0.05, n_jobs: int = 1) -> SearchResult:
    """Add effects one at a time while the selection gain beats ``threshold(round)`` (and, if
    ``lower_q`` is set, while its bootstrap ``lower_q`` quantile stays positive)."""
    current: FitResult | None = None
    before_sse = fitter.heldout_sse()
    rounds: list[Round] = []
    keys: list[str] = []
    pool = dict(candidates)
    for r in range(max_effects):
        thr = threshold(r)
        results, gains = candidate_gains(fitter, pool, current, before_sse, progress, n_jobs)
        lower = {k: gain_lower_bound(before_sse, x.window_sse, q=lower_q or 0.05) for k, x in results.items()}
        group = choose(gains, lower if lower_q else {}, thr)
        before = float(np.sqrt(before_sse.sum() / max(1, sum(f._n_test for f in fitter.folds))))
        if not group:
            rounds.append(Round(before, results, gains, lower, thr))
            break
        winner, kept, basis = (group[0], (group[0],), "alone") if len(group) == 1 else \
            tie_break(fitter, group, results, pool, contexts, gains, noise)
        rounds.append(Round(before, results, gains, lower, thr, winner, kept, basis))
        current = accept(fitter, results[winner], gains[winner], before_sse)
        before_sse = current.window_sse
        keys.append(winner)
        pool.pop(winner)  # the group's other members stay candidates
        if not pool:
            break
    return SearchResult(as_sum(current) if current is not None else None, tuple(rounds), tuple(keys))
