"""Bootstrap CI, permutation test and Holm correction on examples worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from voe.scoring.stats import bootstrap_ci, holm, permutation_pvalue


def test_bootstrap_ci_known_examples():
    assert bootstrap_ci(np.full(7, 0.5)) == (0.5, 0.5)  # blind model: no spread at all
    assert bootstrap_ci(np.ones(5)) == (1.0, 1.0)
    # [0, 0, 0, 1]: the resampled mean is k/4 with k ~ Binomial(4, 1/4):
    # P(0) = .316, P(.25) = .422, P(.5) = .211, P(.75) = .047, P(1) = .004
    # cumulative .316 .738 .949 .996 -> 2.5% quantile 0, 97.5% quantile 0.75
    assert bootstrap_ci(np.array([0, 0, 0, 1.0])) == (0.0, 0.75)
    # [0, 1]: P(mean=0) = 1/4 -> 2.5% quantile 0; P(mean=1) = 1/4 -> 97.5% quantile 1
    assert bootstrap_ci(np.array([0, 1.0])) == (0.0, 1.0)
    assert bootstrap_ci(np.array([0, 1.0, 1.0]), seed=3) == bootstrap_ci(np.array([0, 1.0, 1.0]), seed=3)
    assert all(np.isnan(bootstrap_ci(np.array([]))))


def test_permutation_p_by_enumeration():
    # three hits: only the identity pattern of 2**3 reaches a sum of 3 -> 1/8
    assert permutation_pvalue(np.array([1.0, 1, 1])) == 1 / 8
    # a tie flips to itself: patterns keeping both hits are 2 of 8 -> 1/4
    assert permutation_pvalue(np.array([1.0, 1, 0.5])) == 1 / 4
    # one hit one miss: null sums {+1, 0, 0, -1}, P(>= 0) = 3/4
    assert permutation_pvalue(np.array([1.0, 0])) == 3 / 4
    assert permutation_pvalue(np.full(5, 0.5)) == 1.0  # blind: never significant
    assert permutation_pvalue(np.zeros(4)) == 1.0  # reversed: one-sided test
    assert np.isnan(permutation_pvalue(np.array([])))


def test_permutation_monte_carlo_above_exact_limit():
    p = permutation_pvalue(np.ones(30), n_perm=2000, seed=1)  # true p = 2**-30
    assert p == pytest.approx(1 / 2001, abs=1e-9)
    assert permutation_pvalue(np.full(30, 0.5), n_perm=500) == 1.0


def test_holm_known_example():
    # sorted .005 .01 .03 .04 -> x4 x3 x2 x1 = .02 .03 .06 .04 -> running max .02 .03 .06 .06
    adj = holm(np.array([0.01, 0.04, 0.03, 0.005]))
    np.testing.assert_allclose(adj, [0.03, 0.06, 0.06, 0.02])
    # .5 x2 = 1.0 (capped), .9 x1 = .9 but the step-down keeps the running max 1.0
    np.testing.assert_allclose(holm(np.array([0.5, 0.9])), [1.0, 1.0])
    out = holm(np.array([0.02, np.nan]))
    assert out[0] == 0.02 and np.isnan(out[1])
