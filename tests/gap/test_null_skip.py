"""From the second round on, the null's round is fitted only if the data's round could pass
(``voe.gap.greedy``): some candidate, or where the pair step runs the best pair, gains more than
``min_gain``, the floor under every threshold. Otherwise the answer is the one the search with
every null round fitted gives."""

from __future__ import annotations

import numpy as np
import pytest

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.greedy import greedy
from voe.gap.null import NullSearch

pytestmark = pytest.mark.usefixtures("no_stand_ins")  # made-up fits: nothing to move (``voe.gap.stand_in``)

W = 20
NAMES = ("quadratic_drag", "angular_damping", "linear_drag", "constant_acceleration")


def _key(effect) -> str:
    return "+".join(sorted(e.name for e in effect.parts)) if effect is not None else ""


class _Fitter:
    """Selection errors per window from a table keyed by the effects' names (missing: no change),
    training costs and motions made up per name; every candidate fit is logged."""

    def __init__(self, sse: dict[str, np.ndarray]) -> None:
        self.sse, self.fitted = sse, []
        self.shooter, self.folds = self, [self]
        self.n_rollouts, self._n_test, self.train = 0, W, [None]
        self.refined = 0

    def _result(self, effect, params) -> FitResult:
        return FitResult(effect, params, 0.0, 0.0, self.sse.get(_key(effect), self.sse[""]), (params,))

    def heldout_sse(self) -> np.ndarray:
        return self.sse[""]

    def fit_candidate(self, current, cand) -> FitResult:
        eff = EffectSum((current.effect.parts if current is not None else ()) + cand.parts)
        self.fitted.append(_key(eff))
        return self._result(eff, np.zeros(eff.n_params))

    def refine(self, res):
        self.refined += 1
        return res

    def refit(self, effect, fold_starts, max_nfev=None):
        return self._result(effect, fold_starts[0])

    def cost(self, effect, params) -> float:  # lower for the names later in NAMES, and for fewer parts
        return float(sum(len(NAMES) - NAMES.index(e.name) for e in effect.parts))

    def residuals(self, windows, effect, params) -> list[np.ndarray]:  # every candidate moves differently
        v = np.zeros(len(NAMES))
        for e in (effect.parts if effect is not None else ()):
            v[NAMES.index(e.name)] += 10.0
        return [v]


def _search(data: dict[str, np.ndarray], every_round: bool = False):
    cands = {k: EFFECTS.get(k)() for k in NAMES}
    null_fitter = _Fitter({"": np.ones(W)})  # clean data: no candidate changes anything
    null = NullSearch(null_fitter, cands, alpha=0.05, min_gain=0.05, seed=0)
    res = greedy(_Fitter(data), cands, null.threshold if every_round else null, 3, set(), 1e-3)
    return res, null, null_fitter


def _rounds(res) -> list[tuple]:
    return [(r.winner, r.group, {k: round(g, 12) for k, g in r.gains.items()}) for r in res.rounds]


def test_the_null_round_is_skipped_when_no_data_candidate_reaches_the_floor():
    data = {"": np.ones(W), "quadratic_drag": np.full(W, 0.1),  # round 1: a 68 % gain
            "linear_drag+quadratic_drag": np.full(W, 0.1 * 0.97**2)}  # round 2: at best 3 %, under the 5 % floor
    res, null, null_fitter = _search(data)
    assert res.keys == ("quadratic_drag",) and len(res.rounds) == 2
    assert res.rounds[1].threshold is None and "was not fitted" in res.rounds[1].basis
    assert len(null.result()) == 1 and len(null_fitter.fitted) == len(NAMES)  # round 1's fits only
    assert null_fitter.refined == 0  # nor is round 1's forced candidate refined for it
    ref, ref_null, ref_fitter = _search(data, every_round=True)  # every null round fitted, no pair step
    assert len(ref_null.result()) == 2 and len(ref_fitter.fitted) == 2 * len(NAMES) - 1
    assert ref_fitter.refined == 1
    assert ref.keys == res.keys and _rounds(ref) == _rounds(res)
    assert ref.rounds[1].threshold >= 0.05


def test_the_null_round_is_fitted_when_a_data_candidate_beats_the_floor():
    data = {"": np.ones(W), "quadratic_drag": np.full(W, 0.1),
            "linear_drag+quadratic_drag": np.full(W, 0.1 * 0.9**2)}  # round 2: 10 %, over the floor
    res, null, null_fitter = _search(data)
    assert len(null.result()) == 2 and len(null_fitter.fitted) == 2 * len(NAMES) - 1
    assert null_fitter.refined == 1  # round 1's forced candidate, refined once its next round is fitted
    assert res.rounds[1].threshold == null.result()[1].threshold and res.rounds[1].winner == "linear_drag"
    assert res.keys == ("quadratic_drag", "linear_drag")
    # every model accepted on the way is kept for the check (``voe.gap.check._earlier``)
    assert [k for k, _ in res.accepted] == [("quadratic_drag",), ("quadratic_drag", "linear_drag")]
    assert res.earlier(("quadratic_drag",)).window_sse[0] == 0.1 and res.earlier(res.keys) is res.accepted[-1][1]
    assert res.earlier(("linear_drag",)) is None


def test_the_null_round_is_fitted_when_only_the_data_pair_beats_the_floor():
    # round 2: each of two candidates alone makes things worse, the two together remove the error
    data = {"": np.ones(W), "quadratic_drag": np.full(W, 0.1),
            "angular_damping+quadratic_drag": np.full(W, 0.2), "constant_acceleration+quadratic_drag": np.full(W, 0.3),
            "angular_damping+constant_acceleration+quadratic_drag": np.full(W, 0.001)}
    res, null, null_fitter = _search(data)
    assert len(null.result()) == 2 and len(null_fitter.fitted) == 2 * len(NAMES) - 1
    assert res.keys == ("quadratic_drag", "constant_acceleration", "angular_damping")  # lower training cost first
    assert "fitted jointly" in res.rounds[1].basis
    data["angular_damping+constant_acceleration+quadratic_drag"] = np.full(W, 0.1 * 0.98**2)  # the pair: 2 %
    res, null, null_fitter = _search(data)
    assert res.keys == ("quadratic_drag",) and res.rounds[1].threshold is None
    assert len(null.result()) == 1 and len(null_fitter.fitted) == len(NAMES)
