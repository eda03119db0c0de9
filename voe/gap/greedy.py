"""The greedy loop: add effects one round at a time, each round fitted side by side with the
same round of the null (``voe.gap.null``) and judged against its threshold.

Why its own module: the statistics of a round (gains, bootstrap bounds, groups, tie-breaks) live
in ``voe.gap.search``; this loop only schedules work. The data's round ``r`` and the null's round
``r`` are needed together (the null's round ``r`` is the threshold of the data's), so their
candidate fits share one parallel loop, and the refine of the data's winner shares one with the
refine of the null's forced candidate. Each fit is the one the serial search makes, so results do
not depend on the schedule.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter, as_sum
from voe.gap.null import NullSearch
from voe.gap.search import (
    Round,
    RoundTask,
    accept_all,
    choose,
    covers_contacts,
    fit_rounds,
    gain_lower_bound,
    tie_break,
)


@dataclass(frozen=True)
class SearchResult:
    """What the greedy search accepted (``model`` is None when nothing was) and every round."""

    model: FitResult | None
    rounds: tuple[Round, ...]
    keys: tuple[str, ...]  # candidate key of each accepted part, in order

    @property
    def groups(self) -> list[list[str]]:
        return [list(r.group) for r in self.rounds if r.winner]


def greedy(fitter: FoldedFitter, candidates: dict[str, Effect], null: NullSearch | Callable[[int], float],
           max_effects: int, contexts: set[str], noise: float, progress: Callable[[str], None] | None = None,
           lower_q: float | None = 0.05, n_jobs: int = 1) -> SearchResult:
    """Add effects one at a time while the selection gain beats the null's threshold of the round
    (and, if ``lower_q`` is set, while its bootstrap ``lower_q`` quantile stays positive).

    Args:
        null: the null search (its rounds are fitted alongside), or any ``threshold(round)``.
    """
    paired = null if isinstance(null, NullSearch) else None
    threshold = null.threshold if paired is not None else null
    current: FitResult | None = None
    before_sse = fitter.heldout_sse()
    rounds: list[Round] = []
    keys: list[str] = []
    pool = dict(candidates)
    for r in range(max_effects):
        tasks = [RoundTask(fitter, pool, current, before_sse)]
        if paired is not None and paired.due(r):
            tasks.append(paired.task())
        outs = fit_rounds(tasks, progress, n_jobs)
        if len(outs) > 1:
            paired.record(*outs[1])
        thr = threshold(r)
        results, gains = outs[0]
        lower = {k: gain_lower_bound(before_sse, x.window_sse, q=lower_q or 0.05) for k, x in results.items()}
        group = choose(gains, lower if lower_q else {}, thr)
        before = float(np.sqrt(before_sse.sum() / max(1, sum(f._n_test for f in fitter.folds))))
        if not group:
            rounds.append(Round(before, results, gains, lower, thr))
            break
        winner, kept, basis = (group[0], (group[0],), "alone") if len(group) == 1 else \
            tie_break(fitter, group, results, pool, contexts, gains, noise)
        plain = pool[winner].global_name
        if plain in results and gains[plain] > thr and lower.get(plain, 1.0) > 0 and covers_contacts(fitter, results[winner]):
            kept = (plain,) + tuple(k for k in kept if k != plain)
            winner, basis = plain, f"{winner}'s interval holds every contact: named {plain}, the whole floor"
        rounds.append(Round(before, results, gains, lower, thr, winner, kept, basis))
        pool.pop(winner)  # the group's other members stay candidates
        goes_on = bool(pool) and r + 1 < max_effects
        items = [(fitter, results[winner], gains[winner], before_sse)]
        null_item = paired.pending() if paired is not None and goes_on else None
        refined = accept_all(items + ([null_item] if null_item else []), n_jobs)
        if null_item:
            paired.accepted(refined[1])
        current = refined[0]
        before_sse = current.window_sse
        keys.append(winner)
        if not pool:
            break
    return SearchResult(as_sum(current) if current is not None else None, tuple(rounds), tuple(keys))
