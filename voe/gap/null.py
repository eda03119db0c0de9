"""The null: the identical greedy search run on data simulated from the nominal scene.

Why: a threshold is only fair if it comes from the same procedure the data goes through. The
clean replicate has the recorded episodes' timing, initial states and measured noise; it is
searched with the same candidates, fitting budget, refine step and selection windows as the data,
and one round at a time, on demand: the data's round ``r`` is judged against the best gain round
``r`` reaches on clean data after the null's own best candidates of the earlier rounds were
forced in (a second effect on top of a first can gain by refitting the first; that gain, too, is
what clean data shows).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter
from voe.gap.search import RoundTask, accept_all, fit_rounds, null_threshold


@dataclass(frozen=True)
class NullRound:
    """One null round: its acceptance threshold, every candidate's clean-data gain, the candidate
    forced in for the next round, and quantiles of the bootstrapped best gain."""

    threshold: float
    gains: dict[str, float]
    forced: str | None
    best_quantiles: dict[str, float | None]
    stand_ins: dict[str, float] = field(default_factory=dict)  # members left out (``voe.gap.stand_in``): gains

    def to_dict(self) -> dict:
        return {"threshold_gain": self.threshold, "forced": self.forced, "best_gain_quantiles": self.best_quantiles,
                "gains": {k: round(v, 4) for k, v in self.gains.items() if np.isfinite(v)},
                "stand_ins": {k: round(v, 4) for k, v in self.stand_ins.items() if np.isfinite(v)}}


class NullSearch:
    """Runs the search on clean data round by round.

    ``threshold(r)`` computes the rounds up to ``r`` itself; the greedy loop instead fits the
    null's round alongside the data's (``due``, ``task``, ``record``). Either way every round is
    the same fit; a forced candidate is refined only when its next round is fitted (``task``).
    """

    def __init__(self, fitter: FoldedFitter, candidates: dict[str, Effect], alpha: float, min_gain: float,
                 seed: int, progress: Callable[[str], None] | None = None, n_jobs: int = 1) -> None:
        self.fitter, self.alpha, self.min_gain, self.seed = fitter, alpha, min_gain, seed
        self.progress, self.n_jobs = progress, n_jobs
        self.pool = dict(candidates)
        self.current: FitResult | None = None
        self.before_sse = fitter.heldout_sse()
        self.rounds: list[NullRound] = []
        self._forced: tuple[FitResult, float] | None = None  # forced in, not yet refined

    def due(self, r: int) -> bool:
        """Whether round ``r`` is the next one and needs fitting (not a repeat of the last)."""
        return len(self.rounds) == r and self._open()

    def _open(self) -> bool:
        return bool(self.pool) and not (self.rounds and self.rounds[-1].forced is None)

    def task(self) -> RoundTask:
        """The next round's fits (the pending forced candidate is refined first)."""
        if self._forced is not None:
            self.accepted(accept_all([self.pending()])[0])
        return RoundTask(self.fitter, self.pool, self.current, self.before_sse, self.progress)

    def pending(self) -> tuple[FoldedFitter, FitResult, float, np.ndarray] | None:
        """The refine step owed for the last forced candidate, as ``accept_all`` takes it."""
        return None if self._forced is None else (self.fitter, *self._forced, self.before_sse)

    def accepted(self, refined: FitResult) -> None:
        """The forced candidate, refined, becomes the current model of the next round."""
        self.current, self._forced = refined, None
        self.before_sse = refined.window_sse

    def record(self, results: dict[str, FitResult], gains: dict[str, float],
               stand_ins: dict[str, float] | None = None) -> None:
        """Close a round from its fits (``fit_rounds``'s, stand-ins left out): threshold, quantiles,
        forced candidate."""
        q, best = null_threshold(self.before_sse, results, self.alpha, self.seed)
        finite = {k: g for k, g in gains.items() if np.isfinite(g)}
        thr = float(max(self.min_gain, q, max(finite.values(), default=0.0)))
        forced = max(finite, key=lambda k: finite[k]) if finite else None
        quant = {str(p): (float(np.quantile(best, p)) if best.size else None) for p in (0.5, 0.95, 0.99)}
        self.rounds.append(NullRound(thr, gains, forced, quant, dict(stand_ins or {})))
        if forced is not None:
            self._forced = (results[forced], gains[forced])
            self.pool.pop(forced)

    def threshold(self, r: int) -> float:
        while len(self.rounds) <= r:
            if not self._open():
                self.rounds.append(self.rounds[-1])  # nothing left to force in: same threshold
                continue
            self.record(*fit_rounds([self.task()], self.progress, self.n_jobs)[0])
        return self.rounds[r].threshold

    def result(self) -> tuple[NullRound, ...]:
        return tuple(self.rounds)
