"""The greedy search's trial: a winner whose gain's lower bound is not positive is kept only if
the next round confirms it (``voe.gap.greedy.Trial``)."""

from __future__ import annotations

import numpy as np

from voe.gap.effects import EFFECTS


class _Shooter:
    n_rollouts = 0


class _Fold:
    _n_test = 20


class _TableFitter:
    """A fitter whose selection errors per window come from a table keyed by the effects' names."""

    def __init__(self, table: dict[str, np.ndarray]) -> None:
        self.table, self.shooter, self.folds = table, _Shooter(), [_Fold()]

    def heldout_sse(self) -> np.ndarray:
        return self.table[""]

    def fit_candidate(self, current, cand):
        from voe.gap.effects.base import EffectSum
        from voe.gap.fit import FitResult

        parts = (current.effect.parts if current is not None else ()) + cand.parts
        sse = self.table["+".join(sorted(e.name for e in parts))]
        return FitResult(EffectSum(parts), np.zeros(0), 0.0, 0.0, sse)

    def refine(self, res):
        return res


def test_a_provisional_winner_stays_only_if_the_next_round_confirms_it():
    from voe.gap.greedy import greedy
    from voe.gap.search import gain_lower_bound, window_gain

    base = np.ones(20)
    lin = np.r_[np.full(2, 1e-8), np.full(18, 2.0)]  # (W,) two windows far better, the rest worse
    assert window_gain(base, lin) > 0.1 and gain_lower_bound(base, lin) <= 0  # beats 10 %, lower bound not positive
    both = np.r_[np.full(2, 1e-8), np.full(18, 0.01)]
    cands = {k: EFFECTS.get(k)() for k in ("linear_drag", "quadratic_drag")}
    table = {"": base, "linear_drag": lin, "quadratic_drag": np.full(20, 0.99), "linear_drag+quadratic_drag": both}
    res = greedy(_TableFitter(table), cands, lambda r: 0.1, 3, set(), 1e-3)
    assert res.keys == ("linear_drag", "quadratic_drag") and "confirmed with quadratic_drag" in res.rounds[0].basis
    table["linear_drag+quadratic_drag"] = lin  # the second effect adds nothing: the trial is undone
    res = greedy(_TableFitter(table), cands, lambda r: 0.1, 3, set(), 1e-3)
    assert res.keys == () and res.model is None and res.rounds[0].winner is None
    assert "not confirmed" in res.rounds[0].basis
    res = greedy(_TableFitter(table), cands, lambda r: 0.1, 1, set(), 1e-3)  # no next round: no trial
    assert res.keys == () and len(res.rounds) == 1
