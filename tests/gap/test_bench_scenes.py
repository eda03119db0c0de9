"""The bench's scenes: the joint effects are concealed in a double pendulum whose episodes start
consistent with both joints, and the concealed effect moves the recordings beyond the noise."""

from __future__ import annotations

import numpy as np

from voe.gap.bench import TRUTHS, make_case
from voe.gap.bench_pendulum import PIVOT, double_pendulum_scene, double_pendulum_start
from voe.gap.effects import EFFECTS
from voe.gap.synth import simulate_episode
from voe.gap.truths import scene_kind


def test_joint_effects_have_a_bench_scene():
    assert {"joint_damping", "joint_friction"} <= set(TRUTHS)
    assert scene_kind("joint_damping") == scene_kind("joint_friction") == "double_pendulum"
    assert scene_kind("none") == scene_kind("friction") == scene_kind("linear_drag+restitution") == "arena"


def test_double_pendulum_start_respects_both_joints():
    scene = double_pendulum_scene(np.random.default_rng(0))
    pose0, vel0 = double_pendulum_start(scene, 0.7, -0.4, 2.0, -1.5)
    t = np.arange(101) / 100
    pose = simulate_episode(scene, 0, t, pose0, vel0, None, None, np.zeros((2, 3)), np.random.default_rng(0), 5e-4).pose
    l1, l2 = scene.bodies[0].size[1], scene.bodies[1].size[1]
    np.testing.assert_allclose(np.linalg.norm(pose[:, 0, :2] - np.asarray(PIVOT), axis=1), l1 / 2, atol=1e-4)
    elbow = pose[:, 0, :2] + l1 / 2 * np.stack([np.sin(pose[:, 0, 2]), -np.cos(pose[:, 0, 2])], axis=1)
    np.testing.assert_allclose(np.linalg.norm(pose[:, 1, :2] - elbow, axis=1), l2 / 2, atol=1e-4)
    first = simulate_episode(scene, 0, np.array([0.0, 1e-3]), pose0, vel0, None, None, np.zeros((2, 3)),
                             np.random.default_rng(0), 5e-4).pose
    v = (first[1] - first[0]) / 1e-3  # no jolt at the start: the first millisecond follows the given velocities
    np.testing.assert_allclose(v, vel0, atol=0.06)


def test_concealed_joint_damping_moves_the_recordings():
    case = make_case(np.random.default_rng(3), "joint_damping", episodes=1, duration=2.0)
    assert case.scene.joints and case.params[0] > 0
    p0, v0 = double_pendulum_start(case.scene, 0.8, 1.6, 1.0, -2.0)
    t, rng = case.episodes[0].t, np.random.default_rng(0)
    free = simulate_episode(case.scene, 0, t, p0, v0, None, None, np.zeros((2, 3)), rng, 5e-4).pose
    damped = simulate_episode(case.scene, 0, t, p0, v0, EFFECTS.get("joint_damping")(), case.params,
                              np.zeros((2, 3)), rng, 5e-4).pose
    assert np.max(np.abs(damped - free)[:, :, :2]) > 5e-3  # several times the bench's 1 mm noise
