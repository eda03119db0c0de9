"""The pymunk scene builder against closed-form motion."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from voe.gap.effects import EFFECTS
from voe.sim.scenefile import BodySpec, JointSpec, SceneSpec, SimWorld

from .conftest import flight_scene


def test_free_flight_is_a_parabola():
    t = np.arange(101) / 100
    w = SimWorld(flight_scene(), np.array([[0.0, 1.0, 0.0]]), np.array([[2.0, 3.0, 1.0]]))
    pose = w.run(t, 1e-3)  # (T, 1, 3)
    np.testing.assert_allclose(pose[:, 0, 0], 2 * t, atol=1e-9)
    np.testing.assert_allclose(pose[:, 0, 1], 1 + 3 * t - 0.5 * 9.81 * t**2, atol=6e-3)  # symplectic Euler: O(dt)
    np.testing.assert_allclose(pose[:, 0, 2], t, atol=1e-9)


def test_linear_drag_kicks_match_exponential_decay():
    scene = SceneSpec((0.0, 0.0), flight_scene().bodies)
    eff = EFFECTS.get("linear_drag")()
    t = np.arange(201) / 100
    w = SimWorld(scene, np.zeros((1, 3)), np.array([[2.0, 0.0, 0.0]]))
    pose = w.run(t, 1e-3, lambda s: eff.forces(s, np.array([0.5]), scene))
    exact = 2.0 / 0.5 * (1 - np.exp(-0.5 * t))
    assert np.max(np.abs(pose[:, 0, 0] - exact)) < 5e-3  # 0.1 % of the 3.2 m travelled


def test_pivot_with_full_bias_keeps_pendulum_energy():
    """A frictionless arm from 1.6 rad follows the exact ODE to within 10 mrad over 5 s at 0.5 ms."""
    m, inertia, a1 = 0.147585, 1.091185e-4, 0.147755
    scene = SceneSpec((0.0, -9.81), (BodySpec("arm", "box", mass=m, size=(0.02, 0.09205), moment=inertia),),
                      joints=(JointSpec("arm", None, (0.0, a1), (0.0, 0.0)),))
    th = 1.6
    w = SimWorld(scene, np.array([[a1 * math.sin(th), -a1 * math.cos(th), th]]), np.zeros((1, 3)))
    t = np.arange(501) / 100
    pose = w.run(t, 5e-4)
    big_j = inertia + m * a1**2
    sol = solve_ivp(lambda _, y: [y[1], -m * 9.81 * a1 * math.sin(y[0]) / big_j], (0, 5), [th, 0.0],
                    t_eval=t, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(pose[:, 0, 2] - sol.y[0])) < 0.01
