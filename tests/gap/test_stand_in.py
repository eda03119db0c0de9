"""A later round's member whose own part moves no selection window's prediction is left out of the
round, in the data's search and the null's (``voe.gap.stand_in``)."""

from __future__ import annotations

import numpy as np
import pytest

from voe.gap import search
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.greedy import greedy
from voe.gap.null import NullSearch
from voe.gap.stand_in import STAND_IN_Z, is_stand_in, own_moved

from .test_null_skip import W, _Fitter


def test_a_member_at_its_nominal_values_moves_nothing_and_one_away_from_them_does():
    """``own_moved`` on real selection windows: a quadratic drag fitted with a linear drag on top
    whose own coefficient is its nominal 0 moves no window (the joint fit's gain is the drag's
    re-spotting); at 0.3 /s the linear drag moves the windows by many sigmas."""
    from voe.gap.stages import GapConfig, _folded, prepare

    from .conftest import flight_episodes

    scene, eps = flight_episodes("quadratic_drag", [0.1], n=6, duration=2.0, seed=6)
    cfg = GapConfig()
    p = prepare(scene, eps, ("quadratic_drag", "linear_drag"), cfg)
    data = _folded(p, p.shooter, p.episodes, p.bad, cfg, 6)
    eff = EffectSum((p.candidates["quadratic_drag"], p.candidates["linear_drag"]))

    def moved(lin: float) -> float:
        prm = np.array([0.1, lin])
        return own_moved(data, FitResult(eff, prm, 0.0, 0.0, np.ones(1), (prm,) * len(data.folds)),
                         p.candidates["linear_drag"])

    assert moved(0.0) == 0.0 and is_stand_in(moved(0.0))
    assert moved(0.3) > 10 * STAND_IN_Z and not is_stand_in(moved(0.3))
    blown = FitResult(eff, np.array([0.1, 0.0]), 0.0, 0.0, np.array([np.inf]), (np.array([0.1, 0.0]),) * len(data.folds))
    assert own_moved(data, blown, p.candidates["linear_drag"]) == np.inf  # judged by its gain, as before


@pytest.fixture
def stand_ins(monkeypatch):
    """``own_moved`` made up per candidate name: the names in the returned set move nothing."""
    names: set[str] = set()
    monkeypatch.setattr(search, "own_moved", lambda fitter, res, cand: 0.0 if cand.name in names else np.inf)
    return names


def test_a_stand_in_cannot_win_a_later_round_nor_set_the_nulls_threshold(stand_ins):
    """Round 2's best member (``linear_drag``, 30 % over the drag) is a stand-in: it is left out of
    the data's round (recorded as such) and the next best member (``constant_acceleration``, 20 %)
    wins; in the null's round 2 the stand-in's 25 % does not count toward the threshold. Without
    the stand-in, the same tables name the linear drag (the test can fail)."""
    base, one = np.ones(W), np.full(W, 0.5)
    table = {"": base, "quadratic_drag": one,
             "linear_drag+quadratic_drag": one * 0.7 ** 2, "constant_acceleration+quadratic_drag": one * 0.8 ** 2}
    null_table = {"": base, "quadratic_drag": base * 0.99 ** 2, "linear_drag+quadratic_drag": base * 0.99 ** 2 * 0.75 ** 2}

    def run():
        data, clean = _Fitter(table), _Fitter(null_table)
        cands = {k: EFFECTS.get(k)() for k in ("quadratic_drag", "linear_drag", "constant_acceleration")}
        null = NullSearch(clean, cands, 0.05, 0.05, 0)
        return greedy(data, cands, null, 2, set(), 1e-3, lower_q=None), null

    res, null = run()
    assert res.keys == ("quadratic_drag", "linear_drag")  # the made-up tables alone
    stand_ins.add("linear_drag")
    res, null = run()
    assert res.keys == ("quadratic_drag", "constant_acceleration")
    r2 = res.rounds[1]
    assert "linear_drag" not in r2.gains and r2.stand_ins == {"linear_drag": pytest.approx(0.3)}
    assert r2.to_dict()["stand_ins"] == {"linear_drag": 0.3}
    assert res.rounds[0].stand_ins == {}  # the first round has no earlier parts to re-spot: never asked
    n2 = null.result()[1]
    assert "linear_drag" in n2.stand_ins and n2.threshold < 0.25
