"""Work run ahead in a forked process (voe.gap.parallel, voe.gap.drift.DriftAhead) gives the
serial answer, counts its rollouts, and is used only for the model it was started for."""

from __future__ import annotations

import os
from dataclasses import replace

import pytest

from voe.gap import GapFinder
from voe.gap.drift import DriftAhead, drift_found
from voe.gap.parallel import Ahead

from .conftest import flight_episodes


def test_ahead_runs_in_another_process_and_raises_its_errors():
    with Ahead(os.getpid, 2) as a:
        assert a.forked and a.result() != os.getpid()
    with Ahead(os.getpid, 1) as a:
        assert not a.forked and a.result() == os.getpid()
    with Ahead(lambda: 1 / 0, 2) as a, pytest.raises(ZeroDivisionError):
        a.result()


def test_drift_ahead_gives_the_serial_answer_only_for_the_same_model():
    scene, eps = flight_episodes("quadratic_drag", [0.15], n=4, duration=1.5, seed=7)
    f = GapFinder(effects=("quadratic_drag",), seed=0).fit(scene, eps)
    p, model = f.problem_, f.search_.result.model
    assert model is not None
    n0 = p.shooter.n_rollouts
    serial = drift_found(p, model, f.config, 0)
    spent = p.shooter.n_rollouts - n0
    assert spent > 0
    with DriftAhead(p, model, f.config, 0, n_jobs=2) as ahead:
        assert ahead.ahead.forked
        assert ahead.found(model) == serial
    assert p.shooter.n_rollouts == n0 + 2 * spent  # the forked process's rollouts are counted here
    with DriftAhead(p, model, f.config, 0, n_jobs=2) as ahead:  # the check changed the model: not used
        assert ahead.found(replace(model, params=model.params * 1.5)) is None
    assert p.shooter.n_rollouts == n0 + 2 * spent
