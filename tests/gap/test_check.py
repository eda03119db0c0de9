"""The check stage's replacement of a winner dropped as not established (``voe.gap.check``)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from voe.gap.check import MAX_ALTERNATIVES, _alternative, passing
from voe.gap.effects import EFFECTS
from voe.gap.fit import FitResult
from voe.gap.search import Round

BASE = np.ones(6)  # (W,) selection SSE of the model without the dropped part


def _round(after: dict[str, float]) -> tuple[Round, SimpleNamespace, list]:
    """A round like development case 3629055's second: the winner ``mass[box]`` alone in its
    group, three more candidates that passed it; ``after`` is each candidate's selection SSE per
    window when fitted again in the winner's place."""
    calls: list = []

    def refit(eff, starts, nfev):
        name = eff.parts[-1].name
        calls.append(name)
        return FitResult(eff, starts[0], 0.0, 0.0, np.full(6, after[name]), tuple(starts))

    names = ("mass", "constant_acceleration", "restitution", "point_attractor", "angular_damping")
    mass, acc, rest, attr, ang = (EFFECTS.get(n)(bodies=("box",)) if n == "mass" else EFFECTS.get(n)() for n in names)
    results = {"mass[box]": FitResult(mass, np.array([1.3]), 0, 0),
               "constant_acceleration": FitResult(acc, np.array([0.0, 0.1]), 0, 0),
               "restitution": FitResult(rest, np.array([0.12]), 0, 0),
               "point_attractor": FitResult(attr, np.array([1.4, 1.0, 1.9]), 0, 0),
               "angular_damping": FitResult(ang, np.array([0.01]), 0, 0)}
    gains = {"mass[box]": 0.46, "constant_acceleration": 0.26, "restitution": 0.195, "point_attractor": 0.16,
             "angular_damping": 0.03}
    lower = {"mass[box]": 0.28, "constant_acceleration": 0.05, "restitution": 0.03, "point_attractor": -0.01,
             "angular_damping": 0.01}
    rnd = Round(0.01, results, gains, lower, 0.05, "mass[box]", ("mass[box]",))
    return rnd, SimpleNamespace(fitter=SimpleNamespace(refit=refit, config=SimpleNamespace(refine_nfev=10))), calls


def test_a_dropped_winner_is_replaced_by_another_candidate_that_passed_its_round():
    """3629055: ``restitution`` passed the round but was outside the winner's group, so the old
    code (group members only) never tried it. Refitted in the dropped winner's place, the
    candidate with the larger round gain (it came from refitting the drag) gains nothing."""
    rnd, s, calls = _round({"constant_acceleration": 0.97, "restitution": 0.4, "point_attractor": 0.1})
    assert passing(rnd) == ["mass[box]", "constant_acceleration", "restitution"]  # lower bounds positive only
    model, key = _alternative(s, rnd, {"mass[box]"}, None, (np.zeros(0),), BASE, rnd.threshold)
    assert key == "restitution" and [e.name for e in model.effect.parts] == ["restitution"]
    assert calls == ["constant_acceleration", "restitution"]  # point_attractor did not pass the round


def test_no_replacement_that_does_not_beat_the_threshold_again():
    rnd, s, _ = _round({"constant_acceleration": 0.97, "restitution": 0.95, "point_attractor": 0.1})
    assert _alternative(s, rnd, {"mass[box]"}, None, (np.zeros(0),), BASE, rnd.threshold) is None
    assert _alternative(s, rnd, {"mass[box]", "constant_acceleration", "restitution"}, None, (np.zeros(0),), BASE,
                        rnd.threshold) is None


def test_the_group_comes_first_and_at_most_a_few_are_fitted():
    rnd, s, calls = _round({"constant_acceleration": 0.5, "restitution": 0.4, "angular_damping": 0.6,
                            "point_attractor": 0.1})
    grouped = Round(rnd.before, rnd.results, {**rnd.gains, "angular_damping": 0.45, "point_attractor": 0.44},
                    {**rnd.lower, "point_attractor": 0.2}, 0.05, "mass[box]", ("mass[box]", "angular_damping"))
    order = passing(grouped)
    assert order[:2] == ["mass[box]", "angular_damping"] and order[2] == "point_attractor"
    _, key = _alternative(s, grouped, {"mass[box]"}, None, (np.zeros(0),), BASE, 0.05)
    assert len(calls) == MAX_ALTERNATIVES and key == "point_attractor"
