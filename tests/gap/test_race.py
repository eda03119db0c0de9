"""The race between a round's candidates is run on refined fits (``voe.gap.race``): a true law
whose short first fit stopped in a worse valley than a rival's is refined before the race, not
only the rival that won on first fits."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum, FitContext
from voe.gap.fit import FitResult
from voe.gap.race import contenders, race_group
from voe.gap.search import choose

pytestmark = pytest.mark.usefixtures("no_stand_ins")  # made-up fits: nothing to move (``voe.gap.stand_in``)

KEYS = ("spring_anchor", "constant_acceleration", "linear_drag", "quadratic_drag")


class _Fold:
    _n_test = 20
    ctx = FitContext(None, np.array([0.0, 0.0]), np.array([2.0, 2.0]), 1.0, 1.0)


class _RaceFitter:
    """Selection errors per window from tables keyed by candidate names: ``first`` for first fits,
    ``refined`` for refine steps (a key missing there: the refine changes nothing); identical
    predictions (no window tells candidates apart)."""

    def __init__(self, first: dict[str, np.ndarray], refined: dict[str, np.ndarray]) -> None:
        self.first, self.refined, self.folds = first, refined, [_Fold()]
        self.shooter = self
        self.n_rollouts = 0
        self.refines: list[str] = []

    def heldout_sse(self) -> np.ndarray:
        return self.first[""]

    def fit_candidate(self, current, cand):
        parts = (current.effect.parts if current is not None else ()) + cand.parts
        return FitResult(EffectSum(parts), np.zeros(cand.n_params), 0.0, 0.0, self.first[cand.name])

    def refine(self, res):
        name = res.effect.parts[-1].name
        self.refines.append(name)
        return replace(res, window_sse=self.refined.get(name, res.window_sse), train_cost=-1.0)

    def residuals(self, effect, fold_params) -> list[np.ndarray]:
        return [np.zeros((5, 1, 3)) for _ in range(20)]


def _greedy(fitter, threshold=0.1):
    from voe.gap.greedy import greedy

    cands = {k: EFFECTS.get(k)() for k in KEYS}
    return greedy(fitter, cands, lambda r: threshold, 1, set(), 1e-3)


def test_contenders_are_the_best_first_fits_above_the_threshold_and_only_in_a_race():
    gains = {"a": 0.5, "b": 0.9, "c": 0.05, "d": 0.7, "e": 0.6}
    assert contenders(gains, 0.1) == ["b", "d", "e"]  # best first, at most RACE
    assert contenders(gains, 0.1, k=2) == ["b", "d"]
    assert contenders(gains, 0.8) == []  # one above the threshold: no race (its refine step comes anyway)
    assert contenders(gains, None) == []  # the null's round was skipped: nothing can pass


def test_a_runner_up_whose_refined_fit_predicts_better_wins_the_round():
    first = {"": np.ones(20), "spring_anchor": np.full(20, 0.40), "constant_acceleration": np.full(20, 0.55),
             "linear_drag": np.full(20, 0.98), "quadratic_drag": np.full(20, 0.99)}
    refined = {"constant_acceleration": np.full(20, 0.30)}
    fitter = _RaceFitter(first, refined)
    res = _greedy(fitter)
    assert res.keys == ("constant_acceleration",)
    assert res.model.train_cost == -1.0  # the model is the refined fit
    assert sorted(fitter.refines) == ["constant_acceleration", "spring_anchor"]  # the winner is not refined twice
    r = res.rounds[0]
    assert r.gains["constant_acceleration"] > r.gains["spring_anchor"]  # the round records the refined gains
    assert r.gains["linear_drag"] < 0.1  # below the threshold on its first fit: not a contender, not refined
    assert np.isclose(r.lower["constant_acceleration"], 1 - np.sqrt(0.55))  # the bound stays the first fit's
    # without the refine the first fits decide, as before
    assert _greedy(_RaceFitter(first, {})).keys == ("spring_anchor",)


def test_only_first_fits_decide_what_can_pass():
    """A candidate whose first fit is under the threshold is not refined into the race, and a
    round where one candidate passes alone is decided as before (its refine step once)."""
    first = {"": np.ones(20), "spring_anchor": np.full(20, 0.40), "constant_acceleration": np.full(20, 0.95),
             "linear_drag": np.full(20, 0.98), "quadratic_drag": np.full(20, 0.99)}
    fitter = _RaceFitter(first, {"constant_acceleration": np.full(20, 0.10)})  # would win, were it refined
    res = _greedy(fitter)
    assert res.keys == ("spring_anchor",)
    assert fitter.refines == ["spring_anchor"]


def test_a_refine_that_loses_leaves_the_first_fit_in_the_race():
    first = {"": np.ones(20), "spring_anchor": np.full(20, 0.40), "constant_acceleration": np.full(20, 0.55),
             "linear_drag": np.full(20, 0.98), "quadratic_drag": np.full(20, 0.99)}
    worse = {"spring_anchor": np.full(20, 0.45), "constant_acceleration": np.full(20, 0.60)}
    res = _greedy(_RaceFitter(first, worse))
    assert res.keys == ("spring_anchor",)
    assert res.model.train_cost == 0.0  # the first fit, kept: its refine lost
    assert np.isclose(res.rounds[0].gains["spring_anchor"], 1 - np.sqrt(0.40))


def test_a_refine_adds_members_to_the_group_and_never_removes_one():
    """6219106's shape: two candidates within 10 % on first fits; the refine helps the more
    flexible one more, and both stay in the group (the winner decided on refined fits)."""
    first = {"spring_anchor": 0.889, "constant_acceleration": 0.880, "linear_drag": 0.02}
    refined = {"spring_anchor": 0.907, "constant_acceleration": 0.881, "linear_drag": 0.02}
    lower = dict.fromkeys(first, 0.5)
    assert choose(refined, lower, 0.1) == ["spring_anchor"]  # refined alone: the constant force is out
    assert race_group(first, refined, lower, 0.1) == ["spring_anchor", "constant_acceleration"]
    for gains in (first, refined):  # without a race (first is gains) it is ``choose``
        assert race_group(gains, gains, lower, 0.1) == choose(gains, lower, 0.1)
    assert race_group(first, refined, lower, None) == []
    # 6219041's shape: the refine brings a runner-up into the group, best refined first
    first = {"spring_anchor": 0.872, "constant_acceleration": 0.847}
    refined = {"spring_anchor": 0.871, "constant_acceleration": 0.887}
    assert race_group(first, refined, lower, 0.1) == ["constant_acceleration", "spring_anchor"]


def test_first_fits_within_the_group_stay_candidates_for_the_check():
    """In the search: a rival the refine pulls ahead of the group keeps the first fits' group."""
    first = {"": np.ones(20), "spring_anchor": np.full(20, 0.40), "constant_acceleration": np.full(20, 0.42),
             "linear_drag": np.full(20, 0.98), "quadratic_drag": np.full(20, 0.99)}
    res = _greedy(_RaceFitter(first, {"spring_anchor": np.full(20, 0.20)}))
    assert res.keys == ("spring_anchor",)
    assert res.rounds[0].group == ("spring_anchor", "constant_acceleration")


class _RoundFitter(_RaceFitter):
    """``_RaceFitter`` with tables per round: keys ``(name, parts already in the model)``."""

    def fit_candidate(self, current, cand):
        n = 0 if current is None else len(current.effect.parts)
        parts = (current.effect.parts if current is not None else ()) + cand.parts
        return FitResult(EffectSum(parts), np.zeros(cand.n_params), 0.0, 0.0, self.first[cand.name, n])

    def refine(self, res):
        key = (res.effect.parts[-1].name, len(res.effect.parts) - 1)
        self.refines.append(key[0])
        return replace(res, window_sse=self.refined.get(key, res.window_sse), train_cost=-1.0)


def test_a_trial_is_confirmed_on_first_fits_not_on_the_race_refine():
    """A provisional winner (gain above the threshold, bootstrap bound not positive) must be
    confirmed by the next round's winner on its first fit, as before the race: the refine that
    decided the race does not decide what passes (``voe.gap.race``)."""
    nominal = np.r_[4.0, 4.0, np.ones(18)]  # (W,) two windows carry the first effect's gain
    trial = np.r_[0.01, 0.01, np.full(18, 1.2)]  # better on 2 windows, worse on 18: bound not positive

    def rest(x):
        return np.r_[0.01, 0.01, np.full(18, x)]

    first = {("", 0): nominal, ("spring_anchor", 0): trial}
    first |= {(k, 0): nominal * 0.99 for k in KEYS[1:]}
    first |= {("spring_anchor", 1): trial, ("constant_acceleration", 1): trial,
              ("linear_drag", 1): rest(1.1), ("quadratic_drag", 1): rest(1.11)}  # both pass round 2, bound > 0
    fitter = _RoundFitter(first, {("linear_drag", 1): rest(0.9)})
    fitter.first[""] = nominal
    res = greedy_two(fitter)
    r1, r2 = res.rounds[0], res.rounds[1]
    assert r2.basis.startswith("linear_drag won") and "linear_drag" in fitter.refines  # the race, refined
    # with the first fit the pair (trial + linear_drag) is not better than the nominal on the
    # resamples that miss the two windows: refused, and the trial is undone
    assert res.keys == () and r1.winner is None and "not confirmed" in r1.basis
    # the refined fit alone would have confirmed it
    from voe.gap.search import gain_lower_bound

    assert gain_lower_bound(nominal, rest(0.9)) > 0 >= gain_lower_bound(nominal, rest(1.1))


def greedy_two(fitter):
    from voe.gap.greedy import greedy

    cands = {k: EFFECTS.get(k)() for k in KEYS}
    return greedy(fitter, cands, lambda r: 0.1 if r == 0 else 0.03, 2, set(), 1e-3)
