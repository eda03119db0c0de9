"""Cross-validation over too few episodes: the figure a fold reports comes from its test
episode, simulated with that fold's parameters, never from the episode that selected in it."""

from __future__ import annotations

import numpy as np

from voe.gap import check
from voe.gap.fit import FitResult
from voe.gap.stages import GapConfig, prepare

from .conftest import flight_episodes


def test_each_fold_reports_on_its_test_episode_with_its_own_parameters(monkeypatch):
    scene, eps = flight_episodes(n=3, duration=1.5)
    config = GapConfig()
    p = prepare(scene, eps, ("linear_drag",), config)
    assert p.split.cross_validated
    model = FitResult(p.candidates["linear_drag"], np.array([0.1]), 0.0, 0.0, np.zeros(0),
                      tuple(np.array([k + 0.5]) for k in range(3)))  # fold k's parameter: k + 0.5
    seen = []
    monkeypatch.setattr(check, "verify", lambda shooter, pairs, *a: seen.extend(pairs) or "ver")
    ver, note = check.verify_on_test(p, model, config, 5.0)
    assert ver == "ver" and "test episode" in note and "neither fitted nor selected" in note
    assert {(w.ep, float(par[0])) for w, par in seen} == {(test[0], k + 0.5) for k, (_, _, test) in enumerate(p.split.folds)}
    for k, (fit, sel, _) in enumerate(p.split.folds):  # what fold k reports was not fitted or selected on
        assert all(w.ep not in fit + sel for w, par in seen if par[0] == k + 0.5)
