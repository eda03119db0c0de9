"""The check refits on the windows the search refined its model on, and asks a sparse part's
nominal value directly (development case 6157137: a rolling resistance and a heavier box)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import voe.gap.check as check
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.greedy import SearchResult
from voe.gap.search import Round
from voe.gap.stages import GapConfig

RR, MASS, SPIN = EFFECTS.get("rolling_resistance")(), EFFECTS.get("mass")(bodies=("ball",)), \
    EFFECTS.get("angular_damping")()
KEYS = {"rolling_resistance": RR, "mass[ball]": MASS, "angular_damping": SPIN}
MODEL_SSE = np.full(9, 0.5)  # (W,) the search's model on the selection windows (nominal: 1 each)


class _Fitter:
    """Refits that keep the model's values on the training windows; on a focused subset the mass,
    left last, moves away (6157137: 0.457 -> 0.869, 30 % worse on the selection windows)."""

    def __init__(self, focused: bool) -> None:
        self.focused, self.calls = focused, []
        self.config = SimpleNamespace(refine_nfev=10)
        self.plain: _Fitter | None = None

    def unfocused(self) -> _Fitter:
        self.plain = _Fitter(False)
        return self.plain

    def refit(self, eff, starts, nfev):
        names = tuple(e.name for e in eff.parts)
        self.calls.append(names)
        full = names == ("rolling_resistance", "mass", "angular_damping")
        both = names == ("rolling_resistance", "mass")
        sse = MODEL_SSE if full or (both and not self.focused) else MODEL_SSE * 1.35 if both else np.full(9, 0.9)
        return FitResult(eff, starts[0], 0, 0, sse, tuple(starts))


def _intervals(p, fit_ids, model, ctx, config, seed):
    """rolling resistance and mass established, the spin damping's interval holds 0."""
    ends = {"rolling_resistance": (0.04, 0.08), "mass": (0.3, 0.6), "angular_damping": (0.0, 1e-4)}
    lo, hi = zip(*(ends[e.name] for e in model.effect.parts), strict=True)
    return np.array(lo), np.array(hi)


def _check(monkeypatch, keys: tuple[str, ...], fitter: _Fitter):
    model = FitResult(EffectSum(tuple(KEYS[k] for k in keys)), np.array([0.063, 0.457, 0.0][:len(keys)]), 0, 0,
                      MODEL_SSE)
    monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
    monkeypatch.setattr(check, "model_intervals", _intervals)
    monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
    rounds = tuple(Round(0.01, {}, {}, {}, 0.05, k, (k,)) for k in keys)
    s = SimpleNamespace(result=SearchResult(model, rounds, keys, np.ones(9)), fitter=fitter)
    return check.check_step(SimpleNamespace(split=SimpleNamespace(fit=(0, 1))), SimpleNamespace(z_threshold=5.0),
                            s, GapConfig(), 0)


def test_a_part_at_zero_does_not_earn_its_place_by_refocusing_the_others(monkeypatch):
    fitter = _Fitter(True)
    c = _check(monkeypatch, ("rolling_resistance", "mass[ball]", "angular_damping"), fitter)
    assert c.keys == ("rolling_resistance", "mass[ball]")
    assert [d["effect"] for d in c.dropped] == ["angular_damping"]
    assert "rises 0.0 %" in c.dropped[0]["reason"]  # the same model, refitted on the same windows
    assert fitter.calls == [] and ("rolling_resistance", "mass") in fitter.plain.calls


def test_a_model_refined_on_its_sparse_part_windows_is_refitted_there(monkeypatch):
    fitter = _Fitter(True)
    c = _check(monkeypatch, ("rolling_resistance", "mass[ball]"), fitter)
    assert c.keys == ("rolling_resistance", "mass[ball]")
    assert fitter.plain is None and fitter.calls  # the search's own fitter: the mass was refined focused


def test_a_sparse_part_whose_interval_holds_its_nominal_value_is_asked_directly(monkeypatch):
    asked = []

    def side(shooter, sets, effect, params, j, ctx, lo, hi, bases=None):
        assert bases is None  # a mass is no hinge: its windows are not projected (voe.gap.nuisance)
        asked.append(j)
        return lo, 0.6  # the fitting windows rule the nominal 1 out

    monkeypatch.setattr(check, "replicate_errors", lambda *a: None)
    monkeypatch.setattr(check, "fit_windows", lambda p, ids, config: ["window"] * len(ids))
    monkeypatch.setattr(check, "nominal_side", side)
    p = SimpleNamespace(split=SimpleNamespace(select=(6, 7)), shooter=None, sigma=None)
    # 6157137's mass[ball] 0.457: the parametric replicates widened the interval over 1
    monkeypatch.setattr(check, "intervals", lambda *a: (np.array([0.05]), np.array([1.21])))
    mass = FitResult(EffectSum((MASS,)), np.array([0.457]), 0, 0, MODEL_SSE)
    lo, hi = check.model_intervals(p, (0, 1), mass, None, GapConfig(), 0)
    assert asked == [0] and hi[0] == 0.6
    # a smooth part's local interval stands (4593052: asked directly, a clean constant was named)
    monkeypatch.setattr(check, "intervals", lambda *a: (np.array([-0.01]), np.array([0.05])))
    drag = FitResult(EffectSum((EFFECTS.get("linear_drag")(),)), np.array([0.02]), 0, 0, MODEL_SSE)
    assert check.model_intervals(p, (0, 1), drag, None, GapConfig(), 0)[1][0] == 0.05 and asked == [0]


def test_a_hinge_part_is_asked_with_its_windows_start_velocities_projected_out(monkeypatch):
    # the clean cases 4497285 and 1829321: a rolling resistance fitted to start-speed noise
    asked = []

    def side(shooter, sets, effect, params, j, ctx, lo, hi, bases=None):
        asked.append((j, bases))
        return lo, hi  # not ruled out: the interval still holds zero

    monkeypatch.setattr(check, "replicate_errors", lambda *a: None)
    monkeypatch.setattr(check, "fit_windows", lambda p, ids, config: ["window"] * len(ids))
    monkeypatch.setattr(check, "nominal_side", side)
    monkeypatch.setattr(check, "velocity_bases", lambda shooter, windows, effect, params: ["basis"] * len(windows))
    monkeypatch.setattr(check, "intervals", lambda *a: (np.array([0.0]), np.array([0.011])))
    rr = FitResult(EffectSum((RR,)), np.array([0.0027]), 0, 0, MODEL_SSE)
    arena = SimpleNamespace(split=SimpleNamespace(select=(6, 7)), shooter=None, sigma=None,
                            scene=SimpleNamespace(joints=()))
    lo, hi = check.model_intervals(arena, (0, 1), rr, None, GapConfig(), 0)
    assert asked == [(0, [["basis", "basis"]])] and lo[0] == 0.0
    # on a scene with joints one body's velocity cannot be stepped alone: asked as before
    asked.clear()
    pendulum = SimpleNamespace(**{**vars(arena), "scene": SimpleNamespace(joints=("pivot",))})
    check.model_intervals(pendulum, (0, 1), rr, None, GapConfig(), 0)
    assert asked == [(0, None)]


def test_a_sparse_part_left_alone_by_a_drop_is_refitted_on_its_own_windows(monkeypatch):
    # development cases 8367085 and 8367133: the search's model ends with a dense part, so the
    # check refits on the training windows; once that part is dropped as not established, the
    # mass left alone goes back to the windows it was fitted on in its round
    def holds_zero(p, fit_ids, model, ctx, config, seed):
        ends = {"rolling_resistance": (0.0, 0.1), "mass": (0.3, 0.6)}
        lo, hi = zip(*(ends[e.name] for e in model.effect.parts), strict=True)
        return np.array(lo), np.array(hi)

    fitter = _Fitter(True)
    monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
    model = FitResult(EffectSum((MASS, RR)), np.array([0.457, 0.063]), 0, 0, MODEL_SSE)
    monkeypatch.setattr(check, "model_intervals", holds_zero)
    monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
    keys = ("mass[ball]", "rolling_resistance")
    rounds = tuple(Round(0.01, {}, {}, {}, 0.05, k, (k,)) for k in keys)
    s = SimpleNamespace(result=SearchResult(model, rounds, keys, np.ones(9)), fitter=fitter)
    c = check.check_step(SimpleNamespace(split=SimpleNamespace(fit=(0, 1))), SimpleNamespace(z_threshold=5.0),
                         s, GapConfig(), 0)
    assert [d["effect"] for d in c.dropped] == ["rolling_resistance"] and c.keys == ("mass[ball]",)
    assert fitter.calls == [("mass",)]  # the search's own fitter, which focuses the mass
    assert fitter.plain.calls == [("rolling_resistance",), ("mass",)]  # only the earn-its-place refits, each part
    # without the other, on the training windows as before


def test_a_drop_that_leaves_an_earlier_model_of_the_search_reports_that_model(monkeypatch):
    # development case 2276115: round 1 accepted rolling_resistance 0.0266; a stand-in on top moved it to
    # 0.0326; the stand-in not established, the rolling resistance refitted alone failed short_of_nominal
    # (13.1 %, quantile -2.3 %). The search's own round-1 model is reported instead, as the check judges any.
    monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
    monkeypatch.setattr(check, "model_intervals", _intervals)
    monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
    keys = ("rolling_resistance", "angular_damping")
    model = FitResult(EffectSum((RR, SPIN)), np.array([0.0326, 0.0]), 0, 0, MODEL_SSE)
    first = FitResult(EffectSum((RR,)), np.array([0.0266]), 0, 0, np.full(9, 0.6))
    rounds = tuple(Round(0.01, {}, {}, {}, 0.05, k, (k,)) for k in keys)

    def run(accepted):
        fitter = _Fitter(True)
        s = SimpleNamespace(result=SearchResult(model, rounds, keys, np.ones(9), False, accepted), fitter=fitter)
        c = check.check_step(SimpleNamespace(split=SimpleNamespace(fit=(0, 1))), SimpleNamespace(z_threshold=5.0),
                             s, GapConfig(), 0)
        return c, fitter.calls + (fitter.plain.calls if fitter.plain is not None else [])  # every refit

    c, calls = run(((("rolling_resistance",), first), (keys, model)))
    assert c.keys == ("rolling_resistance",) and c.model is first
    assert [d["effect"] for d in c.dropped] == ["angular_damping"]
    assert calls.count(("rolling_resistance",)) == 1  # its leave-one-out refit only
    c, calls = run(((keys, model),))  # no such model in the search: refitted from where the joint fit left it
    assert c.keys == ("rolling_resistance",) and c.model.params[0] == 0.0326
    assert calls.count(("rolling_resistance",)) == 2  # its leave-one-out refit, then the refit after the drop
