"""The profile scan that replaces a blind interval (``voe.gap.profile``), on a saturated toy model
worked out by hand."""

from __future__ import annotations

import numpy as np

from voe.gap.profile import nominal_side, profile_interval, ruled_out, scan_grid


class _Sticky:
    """A friction-like parameter in [0, 3], nominal 0.6: above 1 the box sticks, so every value
    above 1 predicts the same; below, the prediction moves with it."""

    n_params = 1

    def bounds(self, ctx):
        return np.array([0.0]), np.array([3.0])

    def nominal(self, ctx):
        return np.array([0.6])


class _Shooter:
    """Window i's residual: its own noise plus 0.05 m per unit of (min(p, 1) - 1)."""

    def __init__(self, n: int = 12, seed: int = 0, flat_at: float = 1.0) -> None:
        self.noise = np.random.default_rng(seed).normal(0, 1e-3, (n, 50, 1, 3))
        self.flat_at = flat_at

    def residuals(self, windows, effect, params):
        shift = 0.05 * (min(float(params[0]), self.flat_at) - self.flat_at)
        return [self.noise[w] + shift for w in windows]


def test_scan_grid_is_geometric_over_decades_and_holds_the_extras():
    g = scan_grid(0.05, 20.0, (1.0, 30.0))
    assert np.isclose(g[0], 0.05) and np.isclose(g[-1], 20.0) and 1.0 in g and 30.0 not in g
    assert np.allclose(np.diff(np.log(g[g != 1.0])), np.log(400) / 23)
    lin = scan_grid(0.0, 3.0)
    assert len(lin) == 24 and np.allclose(np.diff(lin), 3 / 23)


def test_equal_predictions_are_never_ruled_out_and_consistently_worse_ones_are():
    fit = np.full(10, 1.0)
    assert not ruled_out(fit, fit.copy())
    assert ruled_out(fit, fit * 4)
    mixed = fit * np.array([4, 0.25] * 5)  # worse on half the windows, better on the other half
    assert not ruled_out(fit, mixed)


def test_saturated_parameter_gets_the_flat_side_and_excludes_the_nominal_value():
    lo, hi = profile_interval(_Shooter(), list(range(12)), _Sticky(), np.array([1.44]), 0, None)
    assert hi == 3.0 and 0.85 < lo <= 1.0 + 3 / 23  # every value >= 1 sticks; the grid step is 3/23
    assert not lo <= 0.6 <= hi


def test_a_parameter_that_moves_nothing_anywhere_keeps_its_whole_range():
    lo, hi = profile_interval(_Shooter(flat_at=-1.0), list(range(12)), _Sticky(), np.array([1.44]), 0, None)
    assert (lo, hi) == (0.0, 3.0)


def test_only_the_windows_a_value_changes_decide_and_one_is_not_enough():
    fit = np.full(18, 1.0)
    sparse = fit.copy()
    sparse[[3, 11]] = 50.0  # the fit is better on the two windows where the box slides, equal elsewhere
    assert ruled_out(fit, sparse)
    one = fit.copy()
    one[3] = 50.0
    assert not ruled_out(fit, one)
    mixed = sparse.copy()
    mixed[[5, 7]] = 1 / 50.0  # and worse on two others: no consistent preference
    assert not ruled_out(fit, mixed)


class _Hinge:
    """A friction-like parameter (``_Sticky``: [0, 3], nominal 0.6) with a hinge at 1 in the windows ``hinge``
    (the body sticks above 1, so the fit at 1.04 has no curvature there, but 0.6 predicts 0.05 m per unit off),
    and window 3 preferring a low value (its own optimum 0.69, 0.02 m per unit). The rest is noise."""

    def __init__(self, hinge: tuple[int, ...] = (0, 1, 7, 8), n: int = 14, seed: int = 0) -> None:
        self.noise = np.random.default_rng(seed).normal(0, 1e-3, (n, 50, 1, 3))
        self.hinge = hinge

    def residuals(self, windows, effect, params):
        v = float(params[0])
        shift = {w: 0.05 * (min(v, 1.0) - 1.0) for w in self.hinge} | {3: 0.02 * (v - 0.69)}
        return [self.noise[w] + shift.get(w, 0.0) for w in windows]


FIT, SELECT = list(range(7)), list(range(7, 14))  # the fitting and the selection windows


def test_a_nominal_value_both_window_sets_rule_out_ends_the_local_interval_short_of_it():
    # the local interval [0, 1.27] holds 0.6 (2758081's shape); the hinge windows of each set rule it out
    lo, hi = nominal_side(_Hinge(), [FIT, SELECT], _Sticky(), np.array([1.04]), 0, None, 0.0, 1.27)
    assert hi == 1.27 and 0.6 < lo <= 1.0 + 3 / 23  # values at or above the hinge predict as the fit there: kept


def test_a_nominal_value_ruled_out_in_one_set_only_keeps_the_local_interval():
    # 2758101's shape: the fitting windows alone rule the nominal value out, the selection windows do not
    assert nominal_side(_Hinge(hinge=(0, 1)), [FIT, SELECT], _Sticky(), np.array([1.04]), 0, None, 0.0, 1.27) \
        == (0.0, 1.27)
    # with both sets as one, the same windows would rule it out
    assert nominal_side(_Hinge(hinge=(0, 1)), [FIT + SELECT], _Sticky(), np.array([1.04]), 0, None, 0.0, 1.27) \
        != (0.0, 1.27)
    # no selection windows (cross-validation): nothing is ruled out here
    assert nominal_side(_Hinge(), [FIT, []], _Sticky(), np.array([1.04]), 0, None, 0.0, 1.27) == (0.0, 1.27)
