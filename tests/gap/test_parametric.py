"""The parametric bootstrap: bias-corrected intervals from replicates simulated under the fit."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import t as student_t

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.parametric import SPREAD, basic_interval, replicate_errors
from voe.gap.stages import GapConfig, context_for, fit_windows, prepare
from voe.gap.uncertainty import established, intervals, one_step, window_terms

from .conftest import flight_episodes


def test_basic_interval_removes_the_bias_and_widens_for_few_replicates():
    errors = np.array([[0.10], [0.12], [0.08], [0.11], [0.09]])  # (R, P): the estimator lands 0.1 high
    lo, hi = basic_interval(np.array([1.1]), errors, spread=1.0)
    half = student_t.ppf(0.975, 4) * np.std(errors, ddof=1) * np.sqrt(1 + 1 / 5)
    assert lo[0] == pytest.approx(1.0 - half) and hi[0] == pytest.approx(1.0 + half)
    assert lo[0] < 1.0 < hi[0] and not lo[0] <= 1.1 - 0.1 - 2 * half  # centred on the corrected value
    lo2, hi2 = basic_interval(np.array([1.1]), errors)  # the finder's: the half-width SPREAD times, same centre
    assert SPREAD > 1 and (lo2[0] + hi2[0]) / 2 == pytest.approx(1.0)
    assert (hi2[0] - lo2[0]) / 2 == pytest.approx(SPREAD * half)
    lo, hi = basic_interval(np.array([1.0, 2.0]), np.array([[0.0, np.nan], [0.1, np.nan], [0.2, 0.3]]))
    assert np.isfinite(lo[0]) and lo[1] == -np.inf and hi[1] == np.inf  # one replicate says nothing of spread


def test_replicates_of_a_drag_fit_cover_it_and_an_empty_second_effect_is_not_established():
    scene, eps = flight_episodes("linear_drag", [0.4], n=6, duration=2.0, seed=6)
    config = GapConfig()
    p = prepare(scene, eps, ("linear_drag",), config)
    ctx = context_for(p.scene, [p.episodes[i] for i in p.split.fit])
    both = EffectSum((EFFECTS.get("linear_drag")(), EFFECTS.get("quadratic_drag")()))
    params = np.array([0.4, 0.0])
    errors = replicate_errors(p, p.split.fit, config.fit_window, both, params, ctx, config.fit.f_scale, 0, n_rep=4)
    assert errors.shape == (4, 2) and np.all(np.isfinite(errors))
    assert np.all(np.abs(errors[:, 0]) < 0.05)  # simulated at the truth, the one-step estimate stays near it
    wins = fit_windows(p, p.split.fit, config)
    lo, hi = intervals(p.shooter, p.sigma, wins, both, params, ctx, config.fit.f_scale, 0, errors)
    assert lo[0] < 0.4 < hi[0] and hi[0] - lo[0] < 0.05
    terms = window_terms(p.shooter, p.sigma, wins, both, params, ctx, config.fit.f_scale)
    p_lo, p_hi = basic_interval(one_step(terms, both, params, ctx), errors)  # widened SPREAD times
    assert lo[0] <= p_lo[0] and p_hi[0] <= hi[0]  # the finder's interval holds the widened parametric one
    assert lo[1] == 0.0 and established(both, lo, hi, ctx) == [True, False]
