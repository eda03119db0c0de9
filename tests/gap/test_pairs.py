"""The pair step (``voe.gap.pairs``): two effects that each make the selection error worse alone
but remove it together are fitted jointly, the pairs chosen by training cost."""

from __future__ import annotations

import numpy as np

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum, FitContext
from voe.gap.fit import FitResult
from voe.gap.pairs import Pair, best_pair, pair_threshold
from voe.gap.search import window_gain

W = 20


def _key(effect) -> str:
    return "+".join(sorted(e.name for e in effect.parts))


class _Shooter:
    n_rollouts = 0

    def __init__(self, moves: dict[str, np.ndarray]) -> None:
        self.moves = moves

    def residuals(self, windows, effect, params) -> list[np.ndarray]:
        return [self.moves[_key(effect) if effect is not None else ""]]


class _Fold:
    ctx = FitContext(None, np.array([0.0, 0.0]), np.array([2.0, 2.0]), 1.0, 1.0)  # attractor points: x, y in [-3, 5] m

    def __init__(self, costs: dict[str, float], moves: dict[str, np.ndarray]) -> None:
        self.costs, self.shooter, self.train = costs, _Shooter(moves), [None]

    def cost(self, effect, params) -> float:
        return self.costs[_key(effect)]


class _TableFitter:
    """Selection errors per window and training costs from tables keyed by the effects' names."""

    def __init__(self, sse: dict[str, np.ndarray], costs: dict[str, float],
                 moves: dict[str, np.ndarray] | None = None) -> None:
        moves = moves or {"": np.zeros(4), **{k: 10.0 * np.eye(4)[i] for i, k in enumerate(costs)}}  # all distinct
        self.sse, self.folds, self.refits = sse, [_Fold(costs, moves)], []
        self.shooter = self.folds[0].shooter

    def refit(self, effect, fold_starts, max_nfev=None) -> FitResult:
        self.refits.append(_key(effect))
        return FitResult(effect, fold_starts[0], 0.0, 0.0, self.sse[_key(effect)], fold_starts)


def _single(name: str, sse: np.ndarray) -> FitResult:
    return FitResult(EffectSum((EFFECTS.get(name)(),)), np.zeros(EFFECTS.get(name)().n_params), 0.0, 0.0, sse)


def test_the_pair_is_chosen_by_training_cost_not_by_the_singles_failed_gains():
    base = np.ones(W)
    sse = {"constant_acceleration": np.full(W, 1.5), "angular_damping": np.full(W, 1.3),  # each worse alone
           "linear_drag": np.full(W, 0.9), "quadratic_drag": np.full(W, 0.95),  # each a little better alone
           "angular_damping+constant_acceleration": np.full(W, 0.01)}
    for a, b in (("linear_drag", "constant_acceleration"), ("angular_damping", "linear_drag"),
                 ("linear_drag", "quadratic_drag"), ("constant_acceleration", "quadratic_drag"),
                 ("angular_damping", "quadratic_drag")):
        sse["+".join(sorted((a, b)))] = np.full(W, 0.85)
    costs = {"constant_acceleration": 10.0, "angular_damping": 20.0, "linear_drag": 30.0, "quadratic_drag": 40.0}
    results = {k: _single(k, sse[k]) for k in costs}
    fitter = _TableFitter(sse, costs)
    pair = best_pair(fitter, results, None, base)
    assert pair is not None and pair.keys == ("constant_acceleration", "angular_damping")
    assert pair.gain == window_gain(base, sse["angular_damping+constant_acceleration"])
    assert len(fitter.refits) == 3 and not any("quadratic_drag" in k for k in fitter.refits)  # top 3 only
    again = best_pair(_TableFitter(sse, costs), results, None, base, n_jobs=2)  # forked workers: same answer
    assert again is not None and (again.keys, again.gain) == (pair.keys, pair.gain)


def test_the_pair_threshold_is_never_below_the_rounds_single_threshold():
    base = np.ones(W)
    assert pair_threshold(None, base, 0.2, 0.05) == 0.2
    null_pair = Pair(("linear_drag", "quadratic_drag"), _single("linear_drag", np.full(W, 0.49)), 0.3)
    thr = pair_threshold(null_pair, base, 0.1, 0.05)
    assert thr >= 0.3 and thr >= window_gain(base, np.full(W, 0.49)) - 1e-12


def test_of_two_fits_that_predict_the_same_motion_the_simpler_is_paired():
    # 3629057: an attractor, a far spring and a constant acceleration all modelled the wind
    base = np.ones(W)
    names = ("point_attractor", "constant_acceleration", "linear_drag", "angular_damping")
    costs = dict(zip(names, (10.0, 12.0, 14.0, 20.0), strict=True))
    wind = np.array([5.0, 5.0, 0.0, 0.0])
    moves = {"": np.zeros(4), "point_attractor": wind + 1.0, "constant_acceleration": wind,
             "linear_drag": np.array([5.0, -5.0, 0.0, 0.0]), "angular_damping": np.array([0.0, 0.0, 1.0, 0.0])}
    sse = {k: np.full(W, 1.2) for k in names}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            sse["+".join(sorted((a, b)))] = np.full(W, 0.8)
    sse["angular_damping+constant_acceleration"] = np.full(W, 0.01)
    fitter = _TableFitter(sse, costs, moves)
    pair = best_pair(fitter, {k: _single(k, sse[k]) for k in names}, None, base)
    assert pair is not None and set(pair.keys) == {"constant_acceleration", "angular_damping"}
    assert not any("point_attractor" in k for k in fitter.refits)  # redundant with the simpler wind


def test_an_attractor_at_its_search_bound_is_paired_as_the_constant_force_it_stands_for():
    # 5250116: the attractor's point ran to the y bound; the constant acceleration ranked just
    # below the top 3 by training cost and was never paired with the spin damping
    base = np.ones(W)
    names = ("angular_damping", "spring_anchor", "point_attractor", "constant_acceleration", "linear_drag")
    costs = dict(zip(names, (10.0, 12.0, 14.0, 14.2, 30.0), strict=True))
    sse = {k: np.full(W, 1.2) for k in names}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            sse["+".join(sorted((a, b)))] = np.full(W, 0.8)
    sse["angular_damping+point_attractor"] = np.full(W, 0.09)
    sse["angular_damping+constant_acceleration"] = np.full(W, 0.085)

    def run(attractor: np.ndarray) -> tuple[Pair | None, list[str]]:
        results = {k: _single(k, sse[k]) for k in names}
        results["point_attractor"] = FitResult(EffectSum((EFFECTS.get("point_attractor")(),)), attractor, 0.0, 0.0,
                                               sse["point_attractor"])
        results["spring_anchor"] = FitResult(EffectSum((EFFECTS.get("spring_anchor")(),)), np.array([0.5, 1.0, 1.0]),
                                             0.0, 0.0, sse["spring_anchor"])  # an anchor among the bodies
        moves = {"": np.zeros(5), **{k: 10.0 * np.eye(5)[i] for i, k in enumerate(names)}}  # all distinct
        fitter = _TableFitter(sse, costs, moves)
        return best_pair(fitter, results, None, base), fitter.refits

    pair, refits = run(np.array([5.0, 1.0, -2.99]))  # y at the lower bound (-3 m): heading for a constant force
    assert pair is not None and set(pair.keys) == {"angular_damping", "constant_acceleration"}
    assert not any("point_attractor" in k for k in refits) and len(refits) == 3
    pair, refits = run(np.array([5.0, 1.0, 1.0]))  # a point among the bodies is a point: paired as before
    assert pair is not None and set(pair.keys) == {"angular_damping", "point_attractor"}
    assert not any("constant_acceleration" in k for k in refits)

