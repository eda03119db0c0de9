"""Work run ahead in a forked process (voe.gap.parallel, voe.gap.drift.DriftAhead,
voe.gap.speculate) gives the serial answer, counts its rollouts, and is used only for the model it
was started for."""

from __future__ import annotations

import multiprocessing as mp
import os
import resource
from dataclasses import replace

import numpy as np
import pytest

from voe.gap import GapFinder
from voe.gap.check import model_intervals
from voe.gap.drift import DriftAhead, drift_found
from voe.gap.parallel import IDLE_NICE, Ahead
from voe.gap.speculate import Speculation
from voe.gap.stages import context_for

from .conftest import flight_episodes


def test_ahead_runs_in_another_process_and_raises_its_errors():
    with Ahead(os.getpid, 2) as a:
        assert a.forked and a.result() != os.getpid()
    with Ahead(os.getpid, 1) as a:
        assert not a.forked and a.result() == os.getpid()
    with Ahead(lambda: 1 / 0, 2) as a, pytest.raises(ZeroDivisionError):
        a.result()


def _user_cpu(n: int) -> float:
    x = 0
    for i in range(n):
        x += i
    return resource.getrusage(resource.RUSAGE_SELF).ru_utime


@pytest.mark.parametrize("idle", [False, True])
def test_an_ahead_process_cpu_is_counted_among_the_callers_children(idle):
    """``bench/gap_speed.py`` reports the finder's CPU as its own plus ``RUSAGE_CHILDREN``: that
    holds only if an ``Ahead`` process is reaped by the time its result is read (a thread, or a
    process left running, would drop its CPU from the line; session 28 suspected this, unmeasured)."""
    k0 = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    with Ahead(lambda: _user_cpu(3_000_000), 2, idle=idle) as a:
        assert a.forked
        spent = a.result()  # the forked process's own user CPU when it finished
    counted = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - k0
    assert spent > 0.05 and counted >= 0.9 * spent


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


def test_idle_ahead_runs_at_the_lowest_priority_until_promoted():
    with Ahead(lambda: os.getpriority(os.PRIO_PROCESS, 0), 2, idle=True) as a:
        assert a.result() == IDLE_NICE
    ctx = mp.get_context("fork")
    started, go = ctx.Event(), ctx.Event()

    def wait() -> int:
        started.set()
        go.wait(60)
        return os.getpriority(os.PRIO_PROCESS, 0)

    mine = os.getpriority(os.PRIO_PROCESS, 0)
    with Ahead(wait, 2, idle=True) as a:
        assert started.wait(60)  # the initializer has lowered the priority by now
        promoted = a.promote()
        go.set()
        assert a.result() == (mine if promoted else IDLE_NICE)  # promoted where permitted (root, RLIMIT_NICE)


def test_speculation_gives_the_serial_checks_only_for_the_same_model():
    scene, eps = flight_episodes("quadratic_drag", [0.15], n=4, duration=1.5, seed=7)
    f = GapFinder(effects=("quadratic_drag",), seed=0).fit(scene, eps)
    p, model = f.problem_, f.search_.result.model
    ctx = context_for(p.scene, [p.episodes[i] for i in p.split.fit])
    n0 = p.shooter.n_rollouts
    lo, hi = model_intervals(p, p.split.fit, model, ctx, f.config, 0)
    drift = drift_found(p, model, f.config, 0)
    spent = p.shooter.n_rollouts - n0
    assert spent > 0
    with Speculation(p, f.config, 0, n_jobs=2) as spec:
        spec.start(model)
        got = spec.intervals(model)
        assert got is not None and np.array_equal(got[0], lo) and np.array_equal(got[1], hi)
        ahead = spec.take("drift", model)
        assert ahead is not None and ahead.result() == drift
    assert p.shooter.n_rollouts == n0 + 2 * spent  # the forked processes' rollouts are counted here
    other = replace(model, params=model.params * 1.5)
    with Speculation(p, f.config, 0, n_jobs=2) as spec:
        spec.start(model)
        assert spec.intervals(other) is None and spec.take("drift", other) is None  # another model: not used
        assert spec.intervals(model) is None  # stopped once refused
    with Speculation(p, f.config, 0, n_jobs=1) as spec:  # one process: nothing runs ahead
        spec.start(model)
        assert spec.intervals(model) is None
    assert p.shooter.n_rollouts == n0 + 2 * spent
