"""A one-parameter fit whose minimum sits at its coarse grid's end walks on outward
(``voe.gap.fit._walk``, session 43). A value still left where a walk ran out of steps, with the
fitting cost falling beyond it, is where the search stopped, not a fit
(``voe.gap.grid_end.beyond_grid``): it is refitted from there and reported only if the refit is a
fit that passes the check's bars, else not at all (``voe.gap.grid_end.past_grid``)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import voe.gap.check as check
import voe.gap.grid_end as grid_end
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult, Fitter
from voe.gap.greedy import SearchResult
from voe.gap.search import Round
from voe.gap.stages import GapConfig

MASS = EffectSum((EFFECTS.get("mass")(bodies=("box",)),))

# development case 6685146 (a floor patch named ``mass[box]`` 3.3, the grid's last ratio):
# cost on the 6 collision windows its fit chose, against the mass ratio
FLOOR_6685146 = {0.2: 605855.0, 0.3: 462348.0, 0.5: 297819.0, 0.75: 194135.0, 1.35: 94926.0, 2.0: 60462.0,
                 2.5: 54295.0, 3.0: 50527.0, 3.3: 48912.0, 4.0: 46671.0, 5.0: 45446.0, 7.0: 45178.0,
                 10.0: 49410.0, 20.0: 56956.0}
# development case 6685007 (a true mass, 2.15, fitted 2.14): the same scan, a minimum inside the grid
MASS_6685007 = {0.2: 123173.0, 0.3: 96399.0, 0.5: 68064.0, 0.75: 40894.0, 1.35: 17182.0, 2.0: 10734.0,
                2.5: 11494.0, 3.0: 12540.0, 3.3: 12929.0, 4.0: 14890.0, 5.0: 16189.0, 7.0: 18463.0,
                10.0: 20957.0, 20.0: 24137.0}
# a true mass of about 4 whose fit stopped at the grid's 3.3 (6685007's scan at twice the ratio; the
# situation of untouched case 2307044, a true joint_friction 0.0200 stopped at 0.0192 in one fold)
MASS_BEYOND = {2 * k: v for k, v in MASS_6685007.items()}


class _Fold:
    """A fold whose fitting cost is interpolated (in log mass) from a development case's scan."""

    def __init__(self, scan: dict[float, float]) -> None:
        self.ctx = None
        self.x, self.y = np.log(list(scan)), np.array(list(scan.values()))

    def focused(self, effect, x0, lo, hi, scale):
        return self

    def cost(self, effect, params):
        return float(np.interp(np.log(params[0]), self.x, self.y))


def _model(value: float) -> FitResult:
    return FitResult(MASS, np.array([value]), 0, 0, np.full(9, 0.5), grid_end=True)


def test_a_value_with_the_cost_falling_beyond_the_grid_is_not_a_fit():
    why = grid_end.beyond_grid(SimpleNamespace(folds=[_Fold(FLOOR_6685146)]), _model(3.3))
    assert why is not None and "where the search stopped" in why
    assert grid_end.beyond_grid(SimpleNamespace(folds=[_Fold(MASS_6685007)]), _model(2.0)) is None  # a minimum


class _Folded:
    """The check's fitter over one ``_Fold``: its refine step goes on to the scan's minimum, where
    the selection windows' errors are ``refit_sse``."""

    def __init__(self, scan: dict[float, float], refit_sse: float) -> None:
        self.folds, self.scan, self.refit_sse = [_Fold(scan)], scan, refit_sse

    def refine(self, res: FitResult) -> FitResult:
        best = np.array([min(self.scan, key=self.scan.get)])
        return FitResult(res.effect, best, 0, 0, np.full(9, self.refit_sse), (best,))


def _check(monkeypatch, scan: dict[float, float], value: float, refit_sse: float, interval=(1.4, 4.6), folded=None):
    """The check of a ``mass[box]`` left at ``value``, the grid's end (selection gain 50 % against
    a 5 % threshold), its refit's selection errors ``refit_sse`` (nominal 1) and intervals ``interval``."""
    monkeypatch.setattr(check, "fit_context", lambda p, ids=None: None)
    monkeypatch.setattr(check, "model_intervals", lambda p, ids, m, ctx, config, seed: (np.array([interval[0]]),
                                                                                        np.array([interval[1]])))
    monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (None, "test"))
    monkeypatch.setattr(check, "selection_z", lambda p, fitter, m: (np.ones(9), np.ones(9)))  # nothing departs
    rounds = (Round(0.01, {}, {}, {}, 0.05, "mass[box]", ("mass[box]",)),)
    s = SimpleNamespace(result=SearchResult(_model(value), rounds, ("mass[box]",), np.ones(9), False),
                        fitter=(folded or _Folded)(scan, refit_sse))
    return check.check_step(SimpleNamespace(split=SimpleNamespace(fit=(0, 1))), SimpleNamespace(z_threshold=5.0),
                            s, GapConfig(), 0)


def test_the_check_drops_a_model_at_its_grid_end_whose_refit_gains_too_little(monkeypatch):
    c = _check(monkeypatch, FLOOR_6685146, 3.3, refit_sse=0.97)  # at 7 the selection gain is 3 %
    assert c.model is None and "where the search stopped" in c.dropped[0]["reason"]
    assert "refitted where the fitting windows want it (7)" in c.dropped[0]["reason"]
    assert _check(monkeypatch, MASS_6685007, 2.0, refit_sse=0.97).keys == ("mass[box]",)  # a minimum: not refitted


def test_the_check_reports_the_refit_of_a_true_effect_stopped_at_its_grid_end(monkeypatch):
    c = _check(monkeypatch, MASS_BEYOND, 3.3, refit_sse=0.4)
    assert c.keys == ("mass[box]",) and c.model.params[0] == 4.0 and not c.dropped
    assert list(c.lower) == [1.4] and list(c.upper) == [4.6]
    c = _check(monkeypatch, MASS_BEYOND, 3.3, refit_sse=0.4, interval=(0.5, 4.6))  # not established there
    assert c.model is None and "its 95 % interval contains the nominal value" in c.dropped[0]["reason"]


def test_the_refit_is_not_reported_when_the_cross_fitted_folds_disagree(monkeypatch):
    """Development case 2307140 (a floor patch): ``friction`` refitted 1.98 and 0.73 in its two
    folds, interval [0.99, 1.50] holding neither."""
    class Halves(_Folded):
        def refine(self, res: FitResult) -> FitResult:
            one = super().refine(res)
            return FitResult(one.effect, one.params, 0, 0, one.window_sse, (one.params * 1.5, one.params / 1.5))

    def run(interval):
        return _check(monkeypatch, MASS_BEYOND, 3.3, refit_sse=0.4, interval=interval, folded=Halves)

    c = run((1.4, 4.6))  # the folds at 6 and 2.67: 6 is outside
    assert c.model is None and "the folds disagree" in c.dropped[0]["reason"]
    assert run((1.4, 6.5)).keys == ("mass[box]",)  # both inside: a fit


def _scalar(cost, effect=MASS, x0=1.0, scale=0.2, nfev=12, bounds=None):
    f = SimpleNamespace(cost=cost)
    lo, hi = bounds or effect.bounds(None)
    return Fitter._scalar(f, effect, np.array([x0]), np.asarray(lo, float), np.asarray(hi, float), np.array([scale]), nfev)


def test_a_one_parameter_fit_walks_past_its_grid_end_to_the_minimum():
    """A minimum at the grid's last point is followed outward (``voe.gap.fit._walk``) until the
    cost rises, then bracketed; a minimum inside the grid is not walked from."""
    x, _, end = _scalar(_Fold(FLOOR_6685146).cost)  # the cost falls on past 3.3 to about 7
    assert 5.0 < x[0] < 10.0 and not end
    x, _, end = _scalar(_Fold(MASS_BEYOND).cost)  # a true mass of about 4
    assert 3.6 < x[0] < 4.8 and not end
    x, _, end = _scalar(_Fold(MASS_6685007).cost)
    assert 1.9 < x[0] < 2.4 and not end


def test_the_walk_finds_a_value_thirty_scales_out():
    """Development seed 6219's ``joint_friction``: the start near zero, the truth 10-30 scales out
    (6219018: 25 scales), where the grid (10 scales) used to stop."""
    drag = EffectSum((EFFECTS.get("linear_drag")(),))
    calls = []

    def cost(effect, params):
        calls.append(float(params[0]))
        return (float(params[0]) - 25.0) ** 2 + 1.0

    x, c, end = _scalar(cost, drag, x0=0.1, scale=1.0, bounds=([0.0], [1e3]))
    assert abs(x[0] - 25.0) < 0.05 and not end
    assert max(calls) < 100  # stepped 10 -> 31 -> 94 (the rise), no further
    assert max(calls[:5]) == 10.1  # the grid alone reaches 10.1 (0.1 + 10 scales), where the fit used to stop


def test_the_walk_goes_down_as_well():
    drag = EffectSum((EFFECTS.get("linear_drag")(),))
    x, _, end = _scalar(lambda e, p: (float(p[0]) + 25.0) ** 2, drag, x0=0.0, scale=1.0, bounds=([-1e3], [1e3]))
    assert abs(x[0] + 25.0) < 0.05 and not end


def test_a_walk_that_reaches_a_bound_stops_there():
    drag = EffectSum((EFFECTS.get("linear_drag")(),))
    x, _, end = _scalar(lambda e, p: -float(p[0]), drag, x0=0.1, scale=1.0, bounds=([0.0], [50.0]))
    assert x[0] == 50.0 and not end  # at the bound: nothing lies beyond, not a grid end


def test_a_walk_that_runs_out_of_steps_is_still_a_grid_end(monkeypatch):
    import voe.gap.fit as fit
    monkeypatch.setattr(fit, "WALK_STEPS", 2)
    drag = EffectSum((EFFECTS.get("linear_drag")(),))
    x, _, end = _scalar(lambda e, p: -float(p[0]), drag, x0=0.1, scale=1.0, bounds=([0.0], [1e6]))
    assert x[0] == 94.1 and end  # 10.1 -> 31.1 -> 94.1, the cost still falling
