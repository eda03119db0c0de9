"""The fast rollouts (windows stepped side by side in C, one force call per kick for all) predict
exactly what ``SimWorld.run`` predicts window by window, and the finder's answer does not change."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import voe.gap.shooting as shooting
from voe.gap import GapFinder
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.rollout import KICK_EVERY, run_many
from voe.gap.shooting import local_state
from voe.gap.stages import context_for
from voe.sim.lockstep import _kick_dts, schedule
from voe.sim.scenefile import BodySpec, JointSpec, SceneSpec, SimWorld

from .conftest import flight_episodes


def _reference(scene, starts, times, substep, effect, params, kick_every=KICK_EVERY):
    """One window at a time through pymunk's own Space.step and Body properties (the slow path)."""
    mats = effect.materials(params, scene) if effect is not None else None
    fn = (lambda st: effect.forces(st, params, scene)) if effect is not None and effect.has_forces else None
    return [SimWorld(scene, p0, v0, mats).run(t, substep, fn, kick_every) for (p0, v0), t in zip(starts, times, strict=True)]


@pytest.fixture(scope="module")
def arena():
    """Windows of an arena case (ball thrown at a box on the floor: flight, impacts, sliding)."""
    case = make_case(np.random.default_rng(1), "none", episodes=2, duration=2.0)
    starts, times = [], []
    for e in case.episodes:
        for k0 in (3, 60, 120):
            pose0, vel0, _ = local_state(e, k0)
            starts.append((pose0, vel0))
            times.append(e.t[k0:k0 + 60 + k0 // 20])  # windows of different lengths
    return case, starts, times


def test_every_effect_is_simulated_bit_for_bit_as_one_window_at_a_time(arena):
    case, starts, times = arena
    ctx = context_for(case.scene, case.episodes)
    names = [n for n in EFFECTS.ids() if EFFECTS.get(n)().applies(case.scene)]
    assert "restitution_region" in names and "rolling_resistance" in names  # callbacks and contact tests covered
    for name in [None, *names]:
        eff = None if name is None else EFFECTS.get(name)(bodies=("box",) if name == "mass" else None)
        p = None if eff is None else np.clip(eff.starts(ctx)[0] + 3 * eff.scale(ctx), *eff.bounds(ctx))
        fast = run_many(case.scene, starts, times, 1e-3, eff, p)
        slow = _reference(case.scene, starts, times, 1e-3, eff, p)
        for a, b in zip(fast, slow, strict=True):
            np.testing.assert_array_equal(a, b, err_msg=f"effect {name}")


def test_kick_intervals_computed_once_are_those_of_every_kick():
    """``_kick_dts`` gives, to the bit, what each kick computed for itself: k times the substep it
    precedes, a finished window keeping its last substep."""
    rng = np.random.default_rng(3)
    hs = [schedule(np.cumsum(np.r_[0.0, rng.uniform(0.008, 0.012, n)]), 1e-3)[0] for n in (7, 12, 9)]
    lengths = [len(h) for h in hs]
    for k in (1, 4, 8):
        got = _kick_dts(hs, lengths, k)
        kicks = range(0, max(lengths), k)
        assert got.shape == (len(kicks), 3)
        want = [[k * h[min(j, n - 1)] for h, n in zip(hs, lengths, strict=True)] for j in kicks]
        assert got.tolist() == want


def test_uneven_time_stamps_and_sums_of_effects(arena):
    case, starts, times = arena
    rng = np.random.default_rng(0)
    jittered = [t + np.concatenate([[0.0], rng.uniform(-3e-3, 3e-3, len(t) - 1)]) for t in times]
    assert len({len(schedule(t, 1e-3)[0]) for t in jittered}) > 1  # the windows take different substeps
    eff = EFFECTS.get("quadratic_drag")() + EFFECTS.get("rolling_resistance")() + EFFECTS.get("angular_damping")()
    p = np.array([0.3, 0.05, 1e-3])
    for a, b in zip(run_many(case.scene, starts, jittered, 1e-3, eff, p),
                    _reference(case.scene, starts, jittered, 1e-3, eff, p), strict=True):
        np.testing.assert_array_equal(a, b)


def test_jointed_scene_with_a_joint_effect():
    scene = SceneSpec((0.0, -9.81), (BodySpec("a", "box", mass=0.2, size=(0.02, 0.1)),
                                     BodySpec("b", "box", mass=0.1, size=(0.02, 0.1))),
                      joints=(JointSpec("a", None, (0.0, 0.05), (0.0, 0.0)), JointSpec("b", "a", (0.0, 0.05), (0.0, -0.05))))
    th = 1.2
    pose0 = np.array([[0.05 * math.sin(th), -0.05 * math.cos(th), th], [0.15 * math.sin(th), -0.15 * math.cos(th), th]])
    starts = [(pose0, np.zeros((2, 3))), (pose0 * 0.9, np.ones((2, 3)) * 0.1)]
    times = [np.arange(81) / 100, np.arange(61) / 100, np.arange(71) / 100]
    starts.append((pose0 * 1.1, -np.ones((2, 3)) * 0.2))
    eff = EFFECTS.get("joint_damping")() + EFFECTS.get("joint_friction")() + EFFECTS.get("angular_damping")()
    p = np.array([2e-4, 1e-3, 1e-4])
    for a, b in zip(run_many(scene, starts, times, 5e-4, eff, p), _reference(scene, starts, times, 5e-4, eff, p),
                    strict=True):
        np.testing.assert_array_equal(a, b)


def test_the_finder_gives_the_same_answer_as_through_the_slow_path(monkeypatch):
    scene, eps = flight_episodes("quadratic_drag", [0.15], n=4, duration=1.5, seed=7)
    few = ("linear_drag", "quadratic_drag", "constant_acceleration")
    fast = GapFinder(effects=few, seed=0, max_effects=2).fit(scene, eps)
    monkeypatch.setattr(shooting, "run_many", _reference)
    slow = GapFinder(effects=few, seed=0, max_effects=2).fit(scene, eps)
    assert fast.effects_ and fast.effects_[0]["name"] == "quadratic_drag"
    assert json.dumps(fast.to_dict(), sort_keys=True) == json.dumps(slow.to_dict(), sort_keys=True)
