"""Re-selection (``voe.gap.reselect``): once a later round has added its effect, an earlier
round's winner gives way to a candidate of its own round that now predicts far better."""

from __future__ import annotations

import numpy as np
import pytest

from voe.gap.effects import EFFECTS

pytestmark = pytest.mark.usefixtures("no_stand_ins")  # made-up fits: nothing to move (``voe.gap.stand_in``)


class _Shooter:
    n_rollouts = 0


class _Fold:
    _n_test = 20


class _Config:
    refine_nfev = 1


class _TableFitter:
    """A fitter whose selection errors per window come from a table keyed by the effects' names
    (any order of parts)."""

    def __init__(self, table: dict[str, np.ndarray]) -> None:
        self.table, self.shooter, self.folds, self.config = table, _Shooter(), [_Fold()], _Config()

    def heldout_sse(self) -> np.ndarray:
        return self.table[""]

    def _result(self, parts: tuple):
        from voe.gap.effects.base import EffectSum
        from voe.gap.fit import FitResult

        eff = EffectSum(parts)
        return FitResult(eff, np.zeros(eff.n_params), 0.0, 0.0, self.table["+".join(sorted(e.name for e in parts))])

    def fit_candidate(self, current, cand):
        if current is not None:
            assert [p.size for p in current.fold_params] == [current.effect.n_params]  # the parts' parameters
        return self._result((current.effect.parts if current is not None else ()) + cand.parts)

    def refine(self, res):
        return res


def _table(swap: float) -> dict[str, np.ndarray]:
    """Like development case 9028132: the spring wins round 1 over the constant, the damping is
    added in round 2, and with the damping in the constant predicts ``swap`` times the spring's
    error."""
    w = np.linspace(0.8, 1.2, 20)  # (W,)
    both = 0.15 * w
    return {"": w, "spring_anchor": 0.3 * w, "constant_acceleration": 0.4 * w, "angular_damping": 0.5 * w,
            "angular_damping+spring_anchor": both, "angular_damping+constant_acceleration": swap * both,
            "constant_acceleration+spring_anchor": 0.29 * w,
            "angular_damping+constant_acceleration+spring_anchor": both}


def test_an_earlier_winner_gives_way_once_the_later_effect_is_in():
    from voe.gap.greedy import greedy

    cands = {k: EFFECTS.get(k)() for k in ("spring_anchor", "constant_acceleration", "angular_damping")}
    res = greedy(_TableFitter(_table(0.05)), cands, lambda r: 0.1, 3, set(), 1e-3)
    assert res.keys == ("constant_acceleration", "angular_damping")
    assert [p.name for p in res.model.effect.parts] == ["constant_acceleration", "angular_damping"]
    assert res.rounds[0].winner == "constant_acceleration" and "re-selected" in res.rounds[0].basis
    assert res.rounds[0].group[:2] == ("constant_acceleration", "spring_anchor")


def test_a_swap_that_gains_less_than_the_rounds_threshold_is_not_made():
    from voe.gap.greedy import greedy

    cands = {k: EFFECTS.get(k)() for k in ("spring_anchor", "constant_acceleration", "angular_damping")}
    res = greedy(_TableFitter(_table(0.9)), cands, lambda r: 0.1, 3, set(), 1e-3)  # gains 5 %, threshold 10 %
    assert res.keys == ("spring_anchor", "angular_damping") and "re-selected" not in res.rounds[0].basis


def test_a_candidate_whose_fit_lost_its_round_is_asked_again_once_the_later_effect_is_in():
    """Like development case 9028134: round 1 fitted the linear drag too strong (the unmodelled
    restitution pulled it; selection gain far below zero) and named the quadratic drag; with the
    restitution in, the linear drag in the quadratic's place predicts far better."""
    from voe.gap.greedy import greedy

    w = np.linspace(0.8, 1.2, 20)  # (W,)
    both = 0.1 * w
    table = {"": w, "quadratic_drag": 0.4 * w, "linear_drag": 3.0 * w, "restitution": 0.9 * w,
             "quadratic_drag+restitution": both, "linear_drag+quadratic_drag": 0.39 * w,
             "linear_drag+restitution": 0.02 * w, "linear_drag+quadratic_drag+restitution": both}
    cands = {k: EFFECTS.get(k)() for k in ("quadratic_drag", "linear_drag", "restitution")}
    res = greedy(_TableFitter(table), cands, lambda r: 0.1, 3, set(), 1e-3)
    assert res.keys == ("linear_drag", "restitution") and "re-selected" in res.rounds[0].basis
    table["linear_drag"] = 0.95 * w  # lost nothing, passed nothing: not asked
    res = greedy(_TableFitter(table), cands, lambda r: 0.1, 3, set(), 1e-3)
    assert res.keys == ("quadratic_drag", "restitution")


def test_the_swaps_run_in_processes_with_the_same_answer():
    """The swaps are asked in ``n_jobs`` forked processes (every part's at once, a later part's
    again after an earlier one was replaced); the answer and the rollout count are those of the
    serial loop."""
    from voe.gap.reselect import reselect

    cands = {k: EFFECTS.get(k)() for k in ("spring_anchor", "constant_acceleration", "angular_damping")}
    table = _table(0.05)
    table["constant_acceleration+spring_anchor"] = 0.2 * table[""]  # round 2's constant passes too: two swaps
    out = []
    for n_jobs in (1, 2):
        fitter = _TableFitter(table)
        res = greedy_rounds(fitter, cands)
        rounds = list(res.rounds)
        model = fitter._result(tuple(cands[k] for k in ("spring_anchor", "angular_damping")))
        fit = fitter.fit_candidate

        def counting(current, cand, fit=fit, fitter=fitter):
            fitter.shooter.n_rollouts += 1
            return fit(current, cand)

        fitter.fit_candidate = counting
        got = reselect(fitter, model, ["spring_anchor", "angular_damping"], rounds, 0.05, n_jobs=n_jobs)
        out.append((got[1], got[2], [r.basis for r in rounds], fitter.shooter.n_rollouts))
    assert out[0][:3] == out[1][:3] and out[0][1] and out[0][0] == ["constant_acceleration", "angular_damping"]
    assert out[1][3] == out[0][3] == 2  # both parts' swaps; the workers' rollouts are counted here


def greedy_rounds(fitter, cands):
    from voe.gap.greedy import greedy

    return greedy(fitter, cands, lambda r: 0.1, 3, set(), 1e-3, lower_q=None)  # the rounds, not re-selected
