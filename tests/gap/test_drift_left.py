"""The drift step asks what is left after a drifting part is dropped again (development case 4446145)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import voe.gap.drift as drift
from voe.gap import GapFinder
from voe.gap.drift import drift_step
from voe.gap.drift_base import Drift
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.folds import as_sum

from .conftest import flight_episodes


def _two_part_case():
    """A small finder run and a checked model of two parts (a drag and a constant), refitted."""
    scene, eps = flight_episodes("linear_drag", [0.3], n=4, duration=1.5, seed=7)
    f = GapFinder(effects=("linear_drag",), seed=0).fit(scene, eps)
    s = f.search_
    eff = EffectSum((EFFECTS.get("linear_drag")(), EFFECTS.get("constant_acceleration")()))
    model = as_sum(s.fitter.refit(eff, tuple(np.array([0.3, 0.0, 0.0]) for _ in s.fitter.folds)))
    c = replace(f.checked_, model=model, keys=("linear_drag", "constant_acceleration"), dropped=())
    return f, s, c


def test_what_is_left_after_a_drifting_part_is_asked_again(monkeypatch):
    """Development case 4446145 (a gust): the constant of ``linear_drag`` + ``constant_acceleration``
    drifted and was dropped; the drag, refitted alone, took up the change (flight t = 4.0) but
    was reported. Here the test answers "the last part drifts" for a model of two parts and "the
    one part drifts" for the refitted drag: both must go."""
    f, s, c = _two_part_case()
    asked = []

    def found(p, model, config, seed, ctx=None):
        n = len(model.effect.parts)
        asked.append(n)
        return [Drift(n - 1, "ax" if n == 2 else "x", "time 0.2 s", -0.27, 0.08, 6.1, flight=n == 1)]

    monkeypatch.setattr(drift, "drift_found", found)
    out = drift_step(f.problem_, f.location_, s, c, f.config, 0)
    assert asked == [2, 1]  # the refitted drag was asked too
    assert out.model is None and out.keys == ()
    assert [d["effect"] for d in out.dropped] == ["constant_acceleration", "linear_drag"]
    assert "in free flight" in out.dropped[1]["reason"]


def test_a_part_left_that_does_not_drift_is_kept(monkeypatch):
    f, s, c = _two_part_case()
    asked = []

    def found(p, model, config, seed, ctx=None):
        n = len(model.effect.parts)
        asked.append(n)
        return [Drift(1, "ax", "time 0.2 s", -0.27, 0.08, 6.1)] if n == 2 else []

    monkeypatch.setattr(drift, "drift_found", found)
    out = drift_step(f.problem_, f.location_, s, c, f.config, 0)
    assert asked == [2, 1]
    assert out.keys == ("linear_drag",) and out.model is not None
    assert [d["effect"] for d in out.dropped] == ["constant_acceleration"]
