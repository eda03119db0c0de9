"""The check's last rule: a model the check built (drops, substitutions) must beat the nominal
model on the selection windows as a whole, as the search asks of every model it accepts."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import voe.gap.check as check
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.greedy import SearchResult
from voe.gap.search import Round, gain_lower_bound
from voe.gap.stages import GapConfig

# development case 4593205 (clean, white): friction alone against the nominal model, per selection
# window half log RMSE ratio; one window carries the whole gain
CLEAN_4593205 = np.array([0.07, 0.0, 0.0, 0.33, 0.0, 0.0, -1.14, 0.0, 0.0])


def _sse(half_log: np.ndarray) -> np.ndarray:
    return np.exp(2 * half_log)  # (W,) against a nominal SSE of 1 per window


def test_a_gain_carried_by_one_window_is_short_of_the_nominal():
    model = FitResult(EffectSum((EFFECTS.get("friction")(),)), np.array([0.56]), 0, 0, _sse(CLEAN_4593205))
    # gain 1 - exp(mean) = 7.9 %: above the 5 % threshold, but not with a positive 5 % quantile
    why = check.short_of_nominal(model, np.ones(9), 0.05, 0.05)
    assert why is not None and "gains 7.9 %" in why and "friction" in why
    assert check.short_of_nominal(model, np.ones(9), 0.05, None) is None  # the threshold alone lets it pass
    assert check.short_of_nominal(model, np.ones(9), 0.08, None) is not None


def test_a_gain_in_every_window_beats_the_nominal():
    model = FitResult(EffectSum((EFFECTS.get("point_attractor")(),)), np.array([1.4, 1.0, 1.9]), 0, 0,
                      _sse(np.full(9, -0.5)))  # 39 % in every window
    assert check.short_of_nominal(model, np.ones(9), 0.05, 0.05) is None
    small = FitResult(model.effect, model.params, 0, 0, _sse(np.full(9, -0.03)))  # 3 %, quantile positive
    assert check.short_of_nominal(small, np.ones(9), 0.05, 0.05) is not None


def _check(monkeypatch: pytest.MonkeyPatch, left_sse: np.ndarray):
    """check_step on a two-part search model (linear_drag, then quadratic_drag) whose first part is
    not established; ``left_sse`` (W,) is what quadratic_drag alone leaves on the selection windows."""
    drag, quad = EFFECTS.get("linear_drag")(), EFFECTS.get("quadratic_drag")()
    both = FitResult(EffectSum((drag, quad)), np.array([0.01, 0.2]), 0, 0, np.full(9, 0.25))

    def refit(eff, starts, nfev):  # the selection errors of whatever is left
        names = [e.name for e in eff.parts]
        sse = {("linear_drag",): np.full(9, 0.9), ("quadratic_drag",): left_sse}[tuple(names)]
        return FitResult(eff, starts[0], 0, 0, sse, tuple(starts))

    def intervals(p, fit_ids, model, ctx, config, seed):  # linear_drag's holds 0, quadratic_drag's not
        lo = np.array([0.1 if e.name == "quadratic_drag" else -0.1 for e in model.effect.parts])
        return lo, lo + 0.2

    monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
    monkeypatch.setattr(check, "model_intervals", intervals)
    monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
    rounds = (Round(0.01, {}, {}, {}, 0.05, "linear_drag", ("linear_drag",)),
              Round(0.01, {}, {}, {}, 0.05, "quadratic_drag", ("quadratic_drag",)))
    fitter = SimpleNamespace(refit=refit, config=SimpleNamespace(refine_nfev=10))
    fitter.unfocused = lambda: fitter  # the refits' windows do not matter here
    s = SimpleNamespace(result=SearchResult(both, rounds, ("linear_drag", "quadratic_drag"), np.ones(9)),
                        fitter=fitter)
    p = SimpleNamespace(split=SimpleNamespace(fit=(0, 1)))
    return check.check_step(p, SimpleNamespace(z_threshold=5.0), s, GapConfig(), 0)


def test_what_the_check_leaves_is_dropped_if_it_does_not_beat_the_nominal(monkeypatch):
    c = _check(monkeypatch, _sse(CLEAN_4593205))  # the pattern of 4593205's friction
    assert c.model is None and c.keys == ()
    assert [d["effect"] for d in c.dropped] == ["linear_drag", "quadratic_drag"]
    assert "against the nominal model on the selection windows" in c.dropped[1]["reason"]


def test_what_the_check_leaves_is_kept_if_it_beats_the_nominal(monkeypatch):
    c = _check(monkeypatch, _sse(np.full(9, -0.5)))
    assert c.keys == ("quadratic_drag",) and [d["effect"] for d in c.dropped] == ["linear_drag"]


def test_an_effect_felt_in_few_windows_is_kept_when_its_quantile_is_exactly_zero():
    # development case 2758072's pattern: a mass changes 2 of 6 selection windows and leaves the
    # others exactly as they were, so resamples without those two gain exactly 0 (8.8 % of them)
    model = FitResult(EffectSum((EFFECTS.get("mass")(),)), np.array([1.3]), 0, 0,
                      _sse(np.array([-1.2, 0.0, 0.0, -0.9, 0.0, 0.0])))
    assert gain_lower_bound(np.ones(6), model.window_sse, q=0.05) == 0.0
    assert check.short_of_nominal(model, np.ones(6), 0.10, 0.05) is None
    worse = FitResult(model.effect, model.params, 0, 0, _sse(np.array([-1.2, 0.05, 0.0, -0.9, 0.0, 0.0])))
    assert check.short_of_nominal(worse, np.ones(6), 0.10, 0.05) is not None  # one window worse: negative


def test_a_model_the_check_left_unchanged_is_judged_too(monkeypatch):
    # one standard for every reported model: a search model nothing was dropped from (here one
    # established part, as a trial kept by ``Trial.last`` would leave it) with 4593205's pattern
    # against the nominal model is not reported; the same model gaining in every window is
    drag = EFFECTS.get("linear_drag")()

    def run(sse: np.ndarray):
        model = FitResult(EffectSum((drag,)), np.array([0.2]), 0, 0, sse)
        monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
        monkeypatch.setattr(check, "model_intervals", lambda p, ids, m, ctx, config, seed: (np.array([0.1]),
                                                                                            np.array([0.3])))
        monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
        rounds = (Round(0.01, {}, {}, {}, 0.05, "linear_drag", ("linear_drag",)),)
        s = SimpleNamespace(result=SearchResult(model, rounds, ("linear_drag",), np.ones(9)), fitter=None)
        return check.check_step(SimpleNamespace(split=SimpleNamespace(fit=(0, 1))), SimpleNamespace(z_threshold=5.0),
                                s, GapConfig(), 0)

    c = run(_sse(CLEAN_4593205))
    assert c.model is None and [d["effect"] for d in c.dropped] == ["linear_drag"]
    assert "against the nominal model on the selection windows" in c.dropped[0]["reason"]
    assert run(_sse(np.full(9, -0.5))).keys == ("linear_drag",)


def test_a_first_round_trial_kept_alone_is_established_by_its_interval(monkeypatch):
    # session 20 (9028098, 9028115): a single effect the search kept as a first-round trial has a
    # negative quantile by construction; the check's interval (fitting episodes) establishes it,
    # so the quantile is not asked again. Not so once the check changed the model, nor without the mark.
    drag = EFFECTS.get("linear_drag")()
    sse = _sse(np.array([-1.5, -0.8, 0.05, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]))  # two windows better, one a little worse
    assert gain_lower_bound(np.ones(9), sse, q=0.05) < 0

    def run(alone: bool, lo: float):
        model = FitResult(EffectSum((drag,)), np.array([0.2]), 0, 0, sse)
        monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
        monkeypatch.setattr(check, "selection_z", lambda p, fitter, m: (np.array([9.0, 6.0]), np.array([2.0, 6.0])))
        monkeypatch.setattr(check, "model_intervals", lambda p, ids, m, ctx, config, seed: (np.array([lo]),
                                                                                            np.array([0.3])))
        monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
        rounds = (Round(0.01, {}, {}, {}, 0.05, "linear_drag", ("linear_drag",)),)
        s = SimpleNamespace(result=SearchResult(model, rounds, ("linear_drag",), np.ones(9), alone), fitter=None)
        return check.check_step(SimpleNamespace(split=SimpleNamespace(fit=(0, 1))), SimpleNamespace(z_threshold=5.0),
                                s, GapConfig(), 0)

    assert run(True, 0.1).keys == ("linear_drag",)
    c = run(False, 0.1)
    assert c.model is None and "against the nominal model on the selection windows" in c.dropped[0]["reason"]
    c = run(True, -0.1)  # the interval holds the nominal value: dropped as not established
    assert c.model is None and "not established" in c.dropped[0]["reason"]


# session 22: selection-window z without and with a first-round trial kept alone (located threshold
# 7.87), development case 4446141 (a gust named ``rolling_resistance``): one window cleared, one
# pushed over, five above either way
GUST_4446141 = (np.array([11.75, 3.88, 9.41, 9.17, 8.53, 7.16, 13.77]),
                np.array([11.76, 2.93, 9.41, 8.96, 8.52, 8.43, 6.15]))
# development case 9028115 (a true ``rolling_resistance``, threshold 5.0): two windows cleared
ROLLING_9028115 = (np.array([4.96, 1.4, 15.93, 1.56, 2.61, 1.68, 1.01, 1.31, 24.46, 3.92, 1.65, 0.73]),
                   np.array([4.87, 1.35, 2.18, 1.56, 2.63, 1.68, 1.61, 1.53, 0.63, 3.92, 1.32, 0.73]))


def test_a_trial_kept_alone_must_clear_a_departure(monkeypatch):
    # a first-round trial kept alone has its quantile waived; a stand-in for physics outside the
    # library (4446141's gust) moves error between windows and clears none, so it is not reported
    drag = EFFECTS.get("linear_drag")()
    sse = _sse(np.array([-1.5, -0.8, 0.05, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]))

    def run(z: tuple[np.ndarray, np.ndarray], z_thr: float):
        model = FitResult(EffectSum((drag,)), np.array([0.2]), 0, 0, sse)
        monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
        monkeypatch.setattr(check, "model_intervals", lambda p, ids, m, ctx, config, seed: (np.array([0.1]),
                                                                                            np.array([0.3])))
        monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
        monkeypatch.setattr(check, "selection_z", lambda p, fitter, m: z, raising=False)  # new in session 22
        rounds = (Round(0.01, {}, {}, {}, 0.05, "linear_drag", ("linear_drag",)),)
        s = SimpleNamespace(result=SearchResult(model, rounds, ("linear_drag",), np.ones(9), True), fitter=None)
        return check.check_step(SimpleNamespace(split=SimpleNamespace(fit=(0, 1))), SimpleNamespace(z_threshold=z_thr),
                                s, GapConfig(), 0)

    c = run(GUST_4446141, 7.87)
    assert c.model is None and [d["effect"] for d in c.dropped] == ["linear_drag"]
    assert "clears no departure" in c.dropped[0]["reason"] and "leaves 5 selection windows" in c.dropped[0]["reason"]
    assert run(ROLLING_9028115, 5.0).keys == ("linear_drag",)


def test_clears_none_counts_windows_above_the_threshold():
    model = FitResult(EffectSum((EFFECTS.get("rolling_resistance")(),)), np.array([0.05]), 0, 0, np.ones(7))
    assert check.clears_none(model, *GUST_4446141, 7.87) is not None  # 5 -> 5
    assert check.clears_none(model, *ROLLING_9028115, 5.0) is None  # 2 -> 0
    assert check.clears_none(model, np.array([1.0, 2.0]), np.array([1.0, 2.0]), 5.0) is not None  # nothing departs
