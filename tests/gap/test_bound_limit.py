"""An effect fitted at the bound where it becomes a simpler effect (a spring anchored at its
search bound is a constant force) is named as that simpler effect when the data cannot tell them
apart (``voe.gap.search.bound_limit``)."""

from __future__ import annotations

import numpy as np
import pytest

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum, FitContext

pytestmark = pytest.mark.usefixtures("no_stand_ins")  # made-up fits: nothing to move (``voe.gap.stand_in``)

CTX = FitContext(None, np.array([0.0, 0.0]), np.array([2.0, 2.0]), 1.0, 1.0)  # spring anchors: x, y in [-3, 5] m


class _Fold:
    _n_test = 20
    ctx = CTX


class _BoundFitter:
    """Selection errors per window from a table keyed by effect names; every candidate's fitted
    parameters from ``params``; identical predictions (no window tells candidates apart)."""

    def __init__(self, sse: dict[str, np.ndarray], params: dict[str, np.ndarray]) -> None:
        self.sse, self.params, self.folds = sse, params, [_Fold()]
        self.shooter = self
        self.n_rollouts = 0

    def heldout_sse(self) -> np.ndarray:
        return self.sse[""]

    def fit_candidate(self, current, cand):
        from voe.gap.fit import FitResult

        parts = (current.effect.parts if current is not None else ()) + cand.parts
        p = np.concatenate([current.params if current is not None else np.zeros(0), self.params[cand.name]])
        return FitResult(EffectSum(parts), p, 0.0, 0.0, self.sse.get("+".join(e.name for e in parts), self.sse[""]))

    def refine(self, res):
        return res

    def residuals(self, effect, fold_params) -> list[np.ndarray]:
        return [np.zeros((5, 1, 3)) for _ in range(20)]


def test_at_limit_is_the_anchor_at_its_search_bound():
    spring = EFFECTS.get("spring_anchor")()
    assert spring.at_limit(np.array([0.05, 5.0, 1.0]), CTX)  # x at the upper bound
    assert spring.at_limit(np.array([0.05, 1.0, -2.97]), CTX)  # y within 1 % of the range from the lower bound
    assert not spring.at_limit(np.array([0.5, 1.0, 1.0]), CTX)  # an anchor among the bodies
    assert not spring.at_limit(np.array([0.0, 1.0, 1.0]), CTX)  # zero stiffness is the nominal, not the limit
    assert not EFFECTS.get("constant_acceleration")().at_limit(np.array([50.0, 50.0]), CTX)  # declares no limit


def test_a_spring_anchored_at_its_bound_is_named_as_the_constant_force_it_stands_for():
    from voe.gap.greedy import greedy

    cands = {k: EFFECTS.get(k)() for k in ("spring_anchor", "constant_acceleration")}
    sse = {"": np.ones(20), "spring_anchor": np.full(20, 0.40), "constant_acceleration": np.full(20, 0.43)}
    ca = np.array([0.7, 0.1])
    at_bound = _BoundFitter(sse, {"spring_anchor": np.array([0.06, 5.0, 1.2]), "constant_acceleration": ca})
    res = greedy(at_bound, cands, lambda r: 0.1, 1, set(), 1e-3)
    assert res.keys == ("constant_acceleration",)
    assert res.rounds[0].group[0] == "constant_acceleration" and "spring_anchor" in res.rounds[0].group
    assert "sits at the bound" in res.rounds[0].basis
    inside = _BoundFitter(sse, {"spring_anchor": np.array([0.5, 1.0, 1.2]), "constant_acceleration": ca})
    assert greedy(inside, cands, lambda r: 0.1, 1, set(), 1e-3).keys == ("spring_anchor",)  # a real anchor stays
    sse["constant_acceleration"] = np.full(20, 0.60)  # the limit predicts clearly worse: out of the group
    assert greedy(at_bound, cands, lambda r: 0.1, 1, set(), 1e-3).keys == ("spring_anchor",)
