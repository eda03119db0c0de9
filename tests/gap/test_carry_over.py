"""The final model must not leave the typical test window departing more than the nominal model
does (``voe.gap.carry_over.worse_on_test``), and the second look's must lower the test-split RMSE by a
practical margin (``voe.gap.carry_over.short_on_test``)."""

from __future__ import annotations

import numpy as np
import pytest

import voe.gap.carry_over as carry
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.stages import GapConfig
from voe.gap.verify import Verification

RR = EffectSum((EFFECTS.get("rolling_resistance")(),))


def _checked(median_before: float, median_after: float, rmse: tuple[float, float] = (0.088, 0.070),
             c: float = 0.048) -> carry.Checked:
    ver = Verification(*rmse, 0.0, 0.0, 0.0, 0.0, median_before, median_after, 1.0, 0.67, False)
    model = FitResult(RR, np.array([c]), 0, 0, np.ones(3))
    return carry.Checked(model, ("rolling_resistance",), np.array([0.02]), np.array([0.05]), (), ver, "test",
                         np.zeros(1))


def test_a_model_that_leaves_the_median_test_window_departing_more_is_not_reported():
    nominal = Verification(0.088, 0.088, 0.0, 0.0, 0.0, 0.0, 18.6, 18.6, 1.0, 1.0, False)
    # development case 6685149 (a gust named ``rolling_resistance``): median window z 18.6 -> 24.4, threshold 5.0
    out = carry.worse_on_test(_checked(18.6, 24.4), None, None, 5.0)
    assert out.model is None and out.keys == () and out.verification == nominal and out.test_note == "test"
    assert "does not carry over" in out.dropped[0]["reason"]
    c = _checked(18.6, 9.5)  # better than nominal: kept
    assert carry.worse_on_test(c, None, None, 5.0) is c
    c = _checked(1.2, 1.4)  # worse, but the typical window does not depart: kept
    assert carry.worse_on_test(c, None, None, 5.0) is c


def _problem(seed: int, truth: str):
    """A white-noise bench case prepared as the finder does: (problem, config, clean replicate's episodes,
    the location's finisher, whose ``z_threshold`` is the located threshold)."""
    from voe.gap.bench import make_case
    from voe.gap.finder import GapFinder
    from voe.gap.stages import GapConfig, locate_parts, prepare

    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind="white")
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(max_effects=1, seed=seed, config=cfg).effects, cfg)
    null_eps, finish = locate_parts(p, cfg, np.random.default_rng(seed))
    return p, cfg, null_eps, finish


def _clean_problem(seed: int = 1078150):
    return _problem(seed, "none")[:3]


def test_a_model_that_makes_a_test_window_depart_beyond_nominal_and_replicate_is_not_reported():
    """``deepened`` lists the test windows where a wrong model adds an error beyond the threshold
    and the clean replicate; the nominal strength itself adds none. Clean data
    with a strong linear drag (2 /s) put in: the ball's flight is mispredicted by centimetres."""
    p, cfg, null_eps = _clean_problem()
    drag = EffectSum((EFFECTS.get("linear_drag")(),))
    wrong = FitResult(drag, np.array([2.0]), 0, 0, np.ones(3))
    deep = carry.deepened(p, wrong, cfg, 5.0, null_eps)
    assert deep and all(a * a - b * b > (cfg.deepen_factor * max(n, 5.0)) ** 2 for b, a, n, _ in deep)
    assert carry.deepened(p, FitResult(drag, np.array([0.0]), 0, 0, np.ones(3)), cfg, 5.0, null_eps) == []
    c = carry.Checked(wrong, ("linear_drag",), np.array([1.9]), np.array([2.1]), (),
                      carry.verify_on_test(p, wrong, cfg, 5.0)[0], "test", np.zeros(1))
    if c.verification.median_z_after > max(c.verification.median_z_before, 5.0):  # the median rule fires first
        c = carry.Checked(wrong, c.keys, c.lower, c.upper, (), Verification(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 2.0,
                          0.0, 0.0, True), "test", np.zeros(1))
    out = carry.worse_on_test(c, p, cfg, 5.0, null_eps)
    assert out.model is None and "itself a departure" in out.dropped[0]["reason"]
    assert carry.worse_on_test(c, p, cfg, 5.0) is c  # without the replicate only the median rule is asked


def test_a_rise_short_of_twice_the_bar_is_kept():
    """A slight wrong drag (0.025 /s) rises one test window by 1.49 times max(replicate z,
    threshold): within what a right name has done on the development seeds (1967005's
    ``joint_friction``, 1.04; 1967085's ``mass[box]`` beside a wrong ``constant_acceleration``,
    1.4), so ``deepened`` (factor 2) keeps it, where a factor of 1 would drop it. (Before restarts
    took the half-step start velocity, session 61, 0.015 /s did 1.45: the restart's own drift
    added to the drag's; now 0.87.)"""
    import dataclasses

    p, cfg, null_eps = _clean_problem()
    slight = FitResult(EffectSum((EFFECTS.get("linear_drag")(),)), np.array([0.025]), 0, 0, np.ones(3))
    assert carry.deepened(p, slight, cfg, 5.0, null_eps) == []
    assert carry.deepened(p, slight, dataclasses.replace(cfg, deepen_factor=1.0, deepen_refit=False), 5.0, null_eps)
    # with its start refitted (session 63) the slight drag's window no longer departs: spared at factor 1 too
    assert carry.deepened(p, slight, dataclasses.replace(cfg, deepen_factor=1.0), 5.0, null_eps) == []


def test_a_right_model_is_not_blamed_for_a_window_that_its_own_motion_makes_chaotic(monkeypatch):
    """Development case 6774127 (a true ``restitution`` of 0.833): the fit (0.8344) clears three of
    the four test windows, but the fourth (episode 11 from sample 12) goes from z 56.9 to 60.8 under
    the fit and to 60.6 under the truth itself: a collision that the lower restitution makes
    chaotic, which the clean replicate (nominal motion, z 1.4) never meets. Its rise, 21.4, passes
    twice the clean bar (14.0), and the right name was dropped; the model's own window-local
    replicates there had a median z of 24.4 (half of ten met the collision), so the rise is what its
    own noise does.

    Since session 61 (restarts take the simulator's half-step start velocity) the window reads
    57.3 -> 61.0, the model's own ten replicates there have a median z of 7.7 (fewer meet the
    collision), and the case's clean replicate meets chaotic windows of its own (located threshold
    25.2, a bar that spares the model by itself). The rule is asked at the case's old threshold
    (6.99): the growth bar spares the model, its own replicates alone no longer do, and replicates
    at the median z they had (24.4) would."""
    import dataclasses

    seed = 6774127
    p, cfg, null_eps, finish = _problem(seed, "restitution")
    assert finish().z_threshold > 20
    z_thr = 6.99
    right = FitResult(EffectSum((p.candidates["restitution"],)), np.array([0.8344]), 0, 0, np.ones(3))
    bare = dataclasses.replace(cfg, deepen_replicates=0, deepen_growth=1.0, deepen_refit=False)
    without = carry.deepened(p, right, bare, z_thr, null_eps)
    assert [round(b) for b, a, n, m in without] == [57] and without[0][3] == 0.0  # the clean bar alone drops it
    own = carry.deepened(p, right, dataclasses.replace(bare, deepen_replicates=10), z_thr, null_eps, seed=seed)
    assert len(own) == 1 and 5.0 < own[0][3] < own[0][1] / 4  # the replicates' median z (7.7) is asked, and is low
    # its window grows x1.06 (57.3 -> 61.0): the growth bar alone (session 42) spares it
    assert carry.deepened(p, right, dataclasses.replace(bare, deepen_growth=1.2), z_thr, null_eps) == []
    monkeypatch.setattr(carry, "local_replicates", lambda *a, **k: np.full((10, 1), 24.4))
    assert carry.deepened(p, right, dataclasses.replace(bare, deepen_replicates=10), z_thr, null_eps, seed=seed) == []


def test_a_right_model_is_not_blamed_for_a_few_per_cent_more_in_a_window_that_already_departs():
    """Development case 6219127 (a true ``restitution`` of 0.736, fitted 0.7341 by the first look):
    the box's impact window in test episode 10 departs at z 71.1 without the model and 74.5 with it
    (x1.05). As a rise, ``sqrt(74.5^2 - 71.1^2)`` = 22, it passes twice the bar (2 x max(threshold 8.3,
    clean replicate 1.8, the model's own replicates 2.8)) and the right name was dropped; the
    window's z has grown by 5 %, not the 20 % (``GapConfig.deepen_growth``) that every misname the
    rule caught had grown it by (x1.29 to x10), so it is kept."""
    import dataclasses

    seed = 6219127
    p, cfg, null_eps, finish = _problem(seed, "restitution")
    z_thr = finish().z_threshold
    right = FitResult(EffectSum((p.candidates["restitution"],)), np.array([0.7341]), 0, 0, np.ones(3))
    old = carry.deepened(p, right, dataclasses.replace(cfg, deepen_growth=1.0, deepen_refit=False), z_thr, null_eps,
                         seed=seed)
    assert [(round(b), round(a)) for b, a, n, m in old] == [(71, 74)]  # growth not asked: dropped
    # the start refit (session 63) spares it by itself too
    assert carry.deepened(p, right, dataclasses.replace(cfg, deepen_growth=1.0), z_thr, null_eps, seed=seed) == []
    assert carry.deepened(p, right, cfg, z_thr, null_eps, seed=seed) == []


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="misnamed since the half step (f67a261): mass[ball] 0.31, whose test window "
                   "rises 27.5 against a clean bar of 31.7, so `deepened` is not asked (docs/gap-findings.md, "
                   "sessions 63 and 65); strict, so that winning the case back shows")
def test_a_floor_patch_fitted_as_a_mass_is_not_reported():
    """Development case 4593142 (a floor patch of other friction, outside the library): the search
    named ``mass[ball]``, which takes one test window from z 38.2 to 49.3 (a rise of 31.1 against
    the threshold 11.4 and the replicate's 2.4); the finder said ``unexplained`` until the half
    step (f67a261), which raised the window's clean bar past its rise. Session 65 measured it on an
    idle machine on main (voe/ as at 471f073): ``mass[ball]`` 0.3139, interval [0.097, 0.445]."""
    from voe.gap.bench import make_case
    from voe.gap.finder import GapFinder
    from voe.gap.stages import GapConfig

    case = make_case(np.random.default_rng(4593142), "floor_patch", 1e-3, 12, 3.0, noise_kind="white")
    f = GapFinder(max_effects=3, seed=4593142, config=GapConfig()).fit(case.scene, case.episodes)
    assert f.effects_ == [] and f.verdict_ == "unexplained"
    assert any("itself a departure" in d["reason"] for d in f.checked_.dropped)


def test_a_second_look_name_that_barely_lowers_the_test_rmse_is_not_reported():
    nominal = Verification(0.00232, 0.00232, 0.0, 0.0, 0.0, 0.0, 2.0, 2.0, 1.0, 1.0, False)
    # development case 6774226 (clean, coloured noise): the second look named rolling_resistance 0.0032,
    # test RMSE 2.32 -> 2.27 mm
    out = carry.short_on_test(_checked(2.0, 2.0, (0.00232, 0.002274), 0.0032), None, GapConfig(), 5.0)
    assert out.model is None and out.keys == () and out.verification == nominal
    assert out.dropped[0]["effect"] == "rolling_resistance" and "2.0 %" in out.dropped[0]["reason"]
    c = _checked(2.0, 2.0, (0.0105, 0.00882))  # a right name's 16.0 % (6774016): kept
    assert carry.short_on_test(c, None, GapConfig(), 5.0) is c
    c = _checked(2.0, 2.0, (0.00232, 0.002274))  # the bar is a setting: 0 keeps every name
    assert carry.short_on_test(c, None, GapConfig(second_look_test_gain=0.0), 5.0) is c
    c = carry.Checked(None, (), np.zeros(0), np.zeros(0), (), nominal, "test", np.zeros(0))
    assert carry.short_on_test(c, None, GapConfig(), 5.0) is c  # nothing named: nothing to drop


def test_the_second_look_test_bar_does_not_judge_a_name_the_test_episodes_do_not_express():
    """Development case 2276003 (a true ``friction``): the second look named it and the test RMSE
    went 5.458 -> 5.520 mm (-1.1 %) because neither test episode slides: no window's prediction
    moved by more than 0.4 mm at a noise of 1 mm. The bar cannot judge it there and keeps the name;
    a name that moves a test window past 3 noise sigmas is judged as before."""
    import dataclasses
    from types import SimpleNamespace

    p = SimpleNamespace(sigma=np.array([[1e-3, 1e-3, 1e-2]] * 2))  # (B, 3): 1 mm in x and y

    def with_moved(moved):
        c = _checked(2.0, 2.0, (0.005458, 0.005520))
        return dataclasses.replace(c, verification=dataclasses.replace(c.verification, moved=moved))

    c = with_moved((0.0004, 0.0001, 0.0, 0.0002))
    assert carry.short_on_test(c, p, GapConfig(), 5.0) is c
    c = with_moved((0.003, 0.0))  # at 3 sigmas exactly: not expressed
    assert carry.short_on_test(c, p, GapConfig(), 5.0) is c
    out = carry.short_on_test(with_moved((0.0031, 0.0)), p, GapConfig(), 5.0)  # expressed, and no better: dropped
    assert out.model is None and "-1.1 %" in out.dropped[0]["reason"]


def test_a_name_the_test_episodes_do_not_express_is_still_dropped_when_it_makes_the_test_worse():
    """Clean case 5905013 (seed 5905, development since its untouched run in session 66): the
    second look named ``constant_acceleration``; no test window moved past 3 sigmas, and the test
    RMSE went 1.378 -> 1.859 mm (-34.9 %). Unexpressed, the test cannot confirm the name, but it
    refutes it: dropped. Worse by less than the bar's margin (5 %), the name is kept."""
    import dataclasses
    from types import SimpleNamespace

    p = SimpleNamespace(sigma=np.array([[1e-3, 1e-3, 1e-2]] * 2))

    def case(after):
        c = _checked(2.0, 2.0, (0.001378, after))
        return dataclasses.replace(c, verification=dataclasses.replace(c.verification, moved=(0.0013, 0.0009)))

    out = carry.short_on_test(case(0.001859), p, GapConfig(), 5.0)
    assert out.model is None and "-34.9 %" in out.dropped[0]["reason"]
    c = case(0.001378 * 1.049)  # 4.9 % worse: within the margin, unexpressed: kept
    assert carry.short_on_test(c, p, GapConfig(), 5.0) is c


def test_the_test_figures_say_how_far_the_model_moves_each_window():
    """``Verification.moved`` is what ``short_on_test`` reads: zero for the nominal model and for a
    model at its nominal value, the RMS change of the prediction otherwise."""
    from voe.gap.stages import prepare

    from .conftest import flight_episodes

    scene, eps = flight_episodes("linear_drag", [0.4], n=6, duration=2.0, seed=6)
    config = GapConfig()
    p = prepare(scene, eps, ("linear_drag",), config)
    drag = p.candidates["linear_drag"]
    ver = carry.verify_on_test(p, FitResult(drag, np.array([0.3]), 0.0, 0.0, np.zeros(0)), config, 5.0)[0]
    assert len(ver.moved) == len(ver.z_before) > 0 and min(ver.moved) > 1e-3  # 0.3 /s of drag moves every window
    none = carry.verify_on_test(p, FitResult(drag, np.array([0.0]), 0.0, 0.0, np.zeros(0)), config, 5.0)[0]
    assert max(none.moved) == 0.0
    assert carry.verify_on_test(p, None, config, 5.0)[0].moved == tuple(0.0 for _ in ver.moved)
    assert ver.nominal().moved == tuple(0.0 for _ in ver.moved)


def test_a_dropped_model_reports_the_nominal_figures_of_its_own_test_windows():
    """``drop_all`` takes the nominal model's figures from the *before* side of the model's own
    verification instead of simulating the test windows again; they must be what simulating gives."""
    from voe.gap.stages import prepare

    from .conftest import flight_episodes

    scene, eps = flight_episodes("linear_drag", [0.4], n=6, duration=2.0, seed=6)
    config = GapConfig()
    p = prepare(scene, eps, ("linear_drag",), config)
    model = FitResult(p.candidates["linear_drag"], np.array([0.3]), 0.0, 0.0, np.zeros(0))
    ver, note = carry.verify_on_test(p, model, config, 5.0)
    assert ver.rmse_after < ver.rmse_before  # the model changes the figures: the test can tell the sides apart
    c = carry.Checked(model, ("linear_drag",), np.array([0.2]), np.array([0.4]), (), ver, note, np.zeros(1))
    out = carry.drop_all(c, "a reason")
    assert out.verification == carry.verify_on_test(p, None, config, 5.0)[0] and out.test_note == note
    assert out.dropped == ({"effect": "linear_drag", "reason": "a reason"},)


def _model(p, name: str, params) -> FitResult:
    """``name`` at ``params`` as the finder's result, the same parameters in every fold."""
    prm = np.asarray(params, float)
    folds = max(1, len(p.split.folds)) if p.split.cross_validated else 1
    return FitResult(EffectSum((p.candidates[name],)), prm, 0, 0, np.ones(3), (prm,) * folds)


def test_a_right_model_is_not_blamed_for_start_noise_that_a_collision_amplifies():
    """Development case 3829008 (a true ``point_attractor``; seed 3829's untouched run, session 63): at the
    truth's own parameters test episode 10's first window goes from z 32.0 to 47.0, a rise past every
    other bar, and the right name was dropped (``unexplained``). Its start velocities, read off the
    noisy poses by a +-5-sample fit, are 28-47 mm/s off; restarted from the noise-free start the truth
    follows to 4.5 mm. With each side's start refitted (``start_noise``), the truth's window is at z
    0.6 and the nominal model's at 26.1: the departure was the start's, not the model's."""
    import dataclasses

    seed = 3829008
    p, cfg, null_eps, finish = _problem(seed, "point_attractor")
    z_thr = finish().z_threshold
    truth = _model(p, "point_attractor", [1.58856277, -1.31383406, 0.80710292])
    old = carry.deepened(p, truth, dataclasses.replace(cfg, deepen_refit=False), z_thr, null_eps, seed=seed)
    assert [round(b) for b, a, n, m in old] == [32]  # dropped without the refit
    assert carry.deepened(p, truth, cfg, z_thr, null_eps, seed=seed) == []


def test_a_misname_still_departs_with_its_start_refitted():
    """Development case 1078143 (a gust, outside the library): the search fitted
    ``rolling_resistance_region`` (c = 0.0414 over x -1.22..3.75 m), which takes a test window from z
    6.0 to 15.0; the refit leaves it at 10.7 against the nominal model's 5.3 and a threshold of 5.4, so
    ``deepened`` still drops it, as designed (session 24)."""
    seed = 1078143
    p, cfg, null_eps, finish = _problem(seed, "gust")
    z_thr = finish().z_threshold
    wrong = _model(p, "rolling_resistance_region", [0.0413690808903756, -1.2174090707027558, 3.7508737825664635])
    deep = carry.deepened(p, wrong, cfg, z_thr, null_eps, seed=seed)
    assert [(round(b), round(a)) for b, a, n, m in deep] == [(6, 15)]
