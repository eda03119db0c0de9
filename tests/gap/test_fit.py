"""Parameter recovery through the simulator and the multiple-shooting fit."""

from __future__ import annotations

import numpy as np

from voe.gap.effects import EFFECTS
from voe.gap.fit import Fitter
from voe.gap.shooting import Shooter, make_windows, noise_floor
from voe.gap.stages import context_for as _context

from .conftest import flight_episodes


def _fitter(scene, eps):
    sigma = noise_floor(eps)
    sh = Shooter(scene, eps, 1e-3, 8)
    train = make_windows(eps, [0, 1, 2], 1.0)
    test = make_windows(eps, [3], 1.0)
    return Fitter(sh, sigma, train, test, _context(scene, eps)), sigma


def test_noise_floor_is_estimated_from_data():
    scene, eps = flight_episodes(noise=2e-3, seed=3)
    sigma = noise_floor(eps)
    np.testing.assert_allclose(sigma[0, :2], 2e-3, rtol=0.15)
    np.testing.assert_allclose(sigma[0, 2], 2e-2, rtol=0.15)


def test_quadratic_drag_coefficient_recovered_within_10_percent():
    scene, eps = flight_episodes("quadratic_drag", [0.12], seed=1)
    fitter, _ = _fitter(scene, eps)
    eff = EFFECTS.get("quadratic_drag")()
    res = fitter.fit(eff, max_nfev=20)
    assert abs(res.params[0] - 0.12) / 0.12 < 0.10
    assert res.heldout_rmse < 0.3 * fitter.heldout(None, None)


def test_constant_acceleration_vector_recovered():
    scene, eps = flight_episodes("constant_acceleration", [0.6, -0.4], seed=2)
    fitter, _ = _fitter(scene, eps)
    res = fitter.fit(EFFECTS.get("constant_acceleration")(), max_nfev=20)
    np.testing.assert_allclose(res.params, [0.6, -0.4], atol=0.06)


def test_point_attractor_is_fitted_from_its_two_most_promising_starts():
    # bench case 5151034: the start near the true point but too strong screened worse than zero
    # strength, and Powell started at zero strength never moved; both starts are now fitted
    scene, eps = flight_episodes("point_attractor", [1.5, 0.5, 2.0], seed=4)
    fitter, _ = _fitter(scene, eps)
    eff = EFFECTS.get("point_attractor")()
    assert eff.multi_start == 2 and EFFECTS.get("linear_drag").multi_start == 1
    zero, near = np.array([0.0, -5.0, 5.0]), np.array([3.0, 0.55, 2.05])
    assert fitter.cost(eff, near) > fitter.cost(eff, zero)  # the screen ranks zero strength first
    res = fitter.fit(eff, [zero, near], max_nfev=12)
    alone = fitter.fit(eff, [zero], max_nfev=12)
    # from zero strength alone the search lands in another valley (a far, strong attractor)
    assert res.train_cost < 0.5 * alone.train_cost and abs(res.params[0] - 1.5) < 0.5


def test_point_attractor_keeps_its_grid_beside_the_regression_starts():
    # development case 7741034: the two flight-regression starts (from noisy twice-differenced
    # accelerations) both lay in a wrong valley, and they used to replace the grid; an effect with
    # several valleys now screens the regression starts together with its grid, which reaches
    # above the highest recorded position (a ball arcs below a point above it)
    from voe.gap.fit import extend

    scene, eps = flight_episodes("point_attractor", [1.5, 0.5, 2.0], seed=4)
    ctx = _context(scene, eps)
    pa, spring = EFFECTS.get("point_attractor")(), EFFECTS.get("spring_anchor")()
    grid = pa.starts(ctx)
    assert len(grid) == 24 and max(s[2] for s in grid) > ctx.hi[1] + 0.9
    assert min(s[1] for s in grid) < ctx.lo[0] and max(s[1] for s in grid) > ctx.hi[0]
    _, starts = extend(None, np.zeros(0), pa, ctx)
    assert len(starts) > len(grid)  # regression starts added, grid kept
    assert all(any(np.array_equal(g, s) for s in starts) for g in grid)
    _, spring_starts = extend(None, np.zeros(0), spring, ctx)
    assert spring.multi_start == 1 and len(spring.starts(ctx)) > 2
    assert len(spring_starts) <= 2  # a one-valley effect still starts from its regression fits only


def test_a_fit_on_the_full_training_windows_holds_their_cost_to_the_bit():
    # voe.gap.pairs._train_cost reuses it instead of simulating every training window again
    scene, eps = flight_episodes("quadratic_drag", [0.12], seed=1)
    fitter, _ = _fitter(scene, eps)
    for name in ("quadratic_drag", "constant_acceleration"):  # bounded Brent and Powell
        eff = EFFECTS.get(name)()
        res = fitter.fit(eff)
        assert res.train_full
        fitter._memo = {}  # noqa: SLF001  # simulated afresh
        n0 = fitter.shooter.n_rollouts
        assert fitter.cost(eff, res.params) == res.train_cost
        assert fitter.shooter.n_rollouts == n0 + len(fitter.train)
