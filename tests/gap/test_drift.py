"""The drift (Chow) test: a constant effect fitted to physics that changes in time is caught."""

from __future__ import annotations

import numpy as np
import pytest

from voe.gap.drift import drifts, material, split_estimates
from voe.gap.drift_base import MATERIAL
from voe.gap.effects import EFFECTS
from voe.gap.parametric import SPREAD
from voe.gap.shooting import Shooter, make_windows, noise_model
from voe.gap.stages import context_for
from voe.gap.uncertainty import window_terms

from .conftest import gusty_episodes


def _pooled_fit(sh, sigma, wins, eff, ctx) -> np.ndarray:
    """Two Gauss-Newton steps on all windows from zero (the model is linear in a constant acceleration)."""
    p = np.zeros(2)
    for _ in range(2):
        hs, gs, _ = window_terms(sh, sigma, wins, eff, p, ctx)
        p = p - np.linalg.solve(hs.sum(axis=0), gs.sum(axis=0))
    return p


def test_a_constant_fitted_to_a_gust_drifts_and_a_true_constant_does_not():
    eff = EFFECTS.get("constant_acceleration")()
    for gust in (True, False):
        scene, eps = gusty_episodes(gust)
        sigma = noise_model(eps)[0]
        sh = Shooter(scene, eps, 1e-3, 8)
        ctx = context_for(scene, eps)
        wins = make_windows(eps, list(range(len(eps))), 0.5, stride=0.25)
        p = _pooled_fit(sh, sigma, wins, eff, ctx)
        found = drifts(sh, sigma, wins, eff, p, ctx)
        if gust:  # the gust's mean differs between early and late windows
            assert len(found) == 1 and found[0].split.startswith("time") and found[0].z > 5
            assert abs(found[0].early - found[0].late) > 0.04 and "changes in time" in found[0].reason()
        else:
            assert abs(p[0] - 0.5) < 0.02 and found == []


def test_split_estimates_worked_example():
    # three windows per side, curvature 1 each; gradients -1, -3, -2 on one side, +1 on the other:
    # one Gauss-Newton step each gives 0 + 6 / 3 = 2 and 0 - 3 / 3 = -1; the spread of the
    # difference is at least the steps' own sqrt(1/3 + 1/3) = 0.816
    hs = np.ones((6, 1, 1))
    gs = np.array([[-1.0], [-3.0], [-2.0], [1.0], [1.0], [1.0]])
    side = np.array([True, True, True, False, False, False])
    a, b, sd = split_estimates(hs, gs, np.zeros(1), side, slice(0, 1), np.random.default_rng(0), spread=1.0)
    np.testing.assert_allclose([a[0], b[0]], [2.0, -1.0], atol=1e-9)
    assert sd[0] >= np.sqrt(2 / 3) - 1e-9 and sd[0] < 1.5
    # the finder's: the same estimates, the sd widened SPREAD times (the windows' understatement)
    a2, b2, sd2 = split_estimates(hs, gs, np.zeros(1), side, slice(0, 1), np.random.default_rng(0))
    np.testing.assert_allclose([a2[0], b2[0]], [2.0, -1.0], atol=1e-9)
    assert SPREAD > 1 and sd2[0] == pytest.approx(SPREAD * sd[0])
    assert split_estimates(hs, gs, np.zeros(1), side, slice(0, 1), np.random.default_rng(0),
                           scale=np.array([0.1])) is None  # curvature 3 x 0.1^2 per scale step: blind
    assert split_estimates(hs[:5], gs[:5], np.zeros(1), side[:5], slice(0, 1),
                           np.random.default_rng(0)) is None  # two windows are no estimate


def test_a_parameter_drift_must_be_material_to_the_parts_strength():
    # 7857006: a linear drag 0.195 in one slot against 0.219 elsewhere is 11 % of its strength
    assert MATERIAL == 0.3
    assert material(np.array([0.195]), np.array([0.219]), np.zeros(1)).tolist() == [False]
    assert material(np.array([0.10]), np.array([0.15]), np.zeros(1)).tolist() == [True]  # 0.05 >= 0.3 * 0.15
    # strength is measured from the nominal value (a friction nominal 0.6: 1.40 against 1.44 is 5 %)
    assert material(np.array([1.40]), np.array([1.44]), np.array([0.6])).tolist() == [False]
    # a vector's strength is its length: a near-zero component is not held to its own size
    assert material(np.array([0.5, 0.0]), np.array([0.52, 0.2]), np.zeros(2)).tolist() == [False, True]
    # a zero-mean gust fitted by a constant: the slots differ by more than the constant itself
    assert material(np.array([0.3, 0.0]), np.array([-0.05, 0.01]), np.zeros(2)).tolist() == [True, False]
    # a parameter without a nominal value (a position) has no floor
    assert material(np.array([0.1, 1.0]), np.array([0.1, 1.001]), np.array([0.0, np.nan])).tolist() == [False, True]
