"""The bench's jointed scene: a double pendulum hanging from a world pivot.

Why: the joint effects (``joint_damping`` on the relative rotation at a pivot between two
bodies, ``joint_friction`` at every pivot) act only where there are joints, and the arena (a ball
and a box on a floor) has none, so without this scene the bench never exercised them. Two thin
rods of random length and mass; each episode starts from random angles and rates chosen so that
both joints turn (the elbow's relative rotation is what ``joint_damping`` resists).
"""

from __future__ import annotations

import numpy as np

from voe.sim.scenefile import BodySpec, JointSpec, SceneSpec

PIVOT = (0.0, 1.5)  # m, world position of the top pivot
WIDTH = 0.04  # m, rod thickness


def double_pendulum_scene(rng: np.random.Generator) -> SceneSpec:
    """Two rods: ``upper`` pivoted to the world at its top end, ``lower`` pivoted to the upper
    rod's bottom end at its own top end. No statics (nothing to hit)."""
    l1, l2 = float(rng.uniform(0.3, 0.5)), float(rng.uniform(0.25, 0.45))
    bodies = (BodySpec("upper", "box", mass=float(rng.uniform(0.5, 1.5)), size=(WIDTH, l1), friction=0.5),
              BodySpec("lower", "box", mass=float(rng.uniform(0.3, 1.0)), size=(WIDTH, l2), friction=0.5))
    joints = (JointSpec("upper", None, (0.0, l1 / 2), PIVOT),
              JointSpec("lower", "upper", (0.0, l2 / 2), (0.0, -l1 / 2)))
    return SceneSpec((0.0, -9.81), bodies, (), joints)


def _rot(th: float, v: tuple[float, float]) -> np.ndarray:
    c, s = np.cos(th), np.sin(th)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _cross(w: float, r: np.ndarray) -> np.ndarray:
    return w * np.array([-r[1], r[0]])


def double_pendulum_start(scene: SceneSpec, th1: float, th2: float, w1: float, w2: float) -> tuple[np.ndarray, np.ndarray]:
    """Pose (2, 3) and velocity (2, 3) of the rods' centres of mass for absolute angles ``th1``,
    ``th2`` (0 hanging down) and rates ``w1``, ``w2`` (rad/s), consistent with both joints."""
    l1, l2 = scene.bodies[0].size[1], scene.bodies[1].size[1]
    pivot = np.asarray(PIVOT)
    c1 = pivot + _rot(th1, (0.0, -l1 / 2))
    elbow = pivot + _rot(th1, (0.0, -l1))
    c2 = elbow + _rot(th2, (0.0, -l2 / 2))
    v1 = _cross(w1, c1 - pivot)
    v2 = _cross(w1, elbow - pivot) + _cross(w2, c2 - elbow)
    pose = np.array([[c1[0], c1[1], th1], [c2[0], c2[1], th2]])
    vel = np.array([[v1[0], v1[1], w1], [v2[0], v2[1], w2]])
    return pose, vel


def random_start(scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A random swing: upper rod within +-70 degrees, lower rod within +-90 degrees of it, rates up
    to 3 rad/s, so both joints turn throughout without the chaos of full rotations."""
    th1 = float(rng.uniform(-1.2, 1.2))
    th2 = th1 + float(rng.uniform(-1.5, 1.5))
    return double_pendulum_start(scene, th1, th2, float(rng.uniform(-3, 3)), float(rng.uniform(-3, 3)))
