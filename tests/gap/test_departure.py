"""The overall departure test behind the verdict ``unexplained``: honest on exchangeable pairs,
decisive on a systematic departure, with few windows too."""

from __future__ import annotations

import numpy as np

from voe.gap.departure import ALPHA, departure_p


def _chaotic(rng: np.random.Generator, n: int) -> np.ndarray:
    """Window z-scores like the bench's clean cases: mostly 1-3, a few chaotic ones up to ~50."""
    z = np.exp(rng.normal(0.5, 0.5, n))
    wild = rng.random(n) < 0.15
    z[wild] *= np.exp(rng.uniform(1, 3, wild.sum()))
    return z


def test_level_is_honest_on_exchangeable_windows():
    rng = np.random.default_rng(0)
    ps = np.array([departure_p(_chaotic(rng, n), _chaotic(rng, n)) for n in rng.integers(4, 30, 600)])
    assert np.mean(ps < ALPHA) <= 0.025  # nominal 1 %
    assert 0.3 < np.median(ps) < 0.7


def test_systematic_departure_is_found_but_one_wild_window_is_not():
    rng = np.random.default_rng(1)
    z0 = _chaotic(rng, 20)
    assert departure_p(3 * z0 * np.exp(rng.normal(0, 0.5, 20)), z0) < 1e-3  # every window worse: missing physics
    one = z0 * np.exp(rng.normal(0, 0.3, 20))
    one[4] = 500.0  # one chaotic window far beyond anything in the replicate
    assert departure_p(one, z0) > ALPHA
    assert departure_p(np.full(4, 150.0), np.array([3.0, 4.0, 2.5, 5.0])) < ALPHA  # few windows, big gap
    assert departure_p(np.array([np.inf, 2.0, 3.0]), np.array([2.0, 2.0, 3.0])) == 1.0  # too few to say
