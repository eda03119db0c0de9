"""A window's start-velocity error must not read as an effect (``voe.gap.nuisance``)."""

from __future__ import annotations

import numpy as np

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.nuisance import profiled_terms, projected_sse, velocity_bases
from voe.gap.profile import nominal_side
from voe.gap.shooting import Shooter, Window, window_sse
from voe.gap.stages import context_for
from voe.gap.synth import simulate_episode
from voe.gap.uncertainty import window_terms
from voe.sim.scenefile import BodySpec, SceneSpec, StaticSpec


def test_a_rolling_balls_slip_from_its_start_estimate_is_not_read_as_drag():
    """Like development case 1531045: a rolling ball's estimated spin 0.5 rad/s off the rolling
    constraint; the simulated ball slips, friction ends the slip at once, and the window's one
    Gauss-Newton step took the changed speed for a different drag (there c = 0.119 against a
    true 0.183). With the start velocity profiled out the step stays at the truth."""
    r = 0.1
    scene = SceneSpec((0.0, -9.81), (BodySpec("ball", "circle", mass=1.0, radius=r, friction=0.6, elasticity=0.5),),
                      (StaticSpec((-8.0, 0.0), (8.0, 0.0), 0.0, 1.0, 1.0),), ())
    drag = EffectSum((EFFECTS.get("linear_drag")(),))
    c = np.array([0.2])
    t = np.arange(101) / 100.0
    pose0, vel0 = np.array([[0.0, r, 0.0]]), np.array([[1.5, 0.0, -1.5 / r]])  # rolling
    rng = np.random.default_rng(0)
    ep = simulate_episode(scene, 0, t, pose0, vel0, drag, c, np.zeros((1, 3)), rng)  # noise-free recording
    sigma = np.array([[1e-3, 1e-3, 1e-2]])
    sh = Shooter(scene, [ep], 1e-3, 5)
    w = Window(0, 30, 80)
    pose, vel, sxx = sh.initial(0, 30)
    sh._ic[(0, 30)] = (pose, vel + np.array([[0.0, 0.0, 0.5]]), sxx)  # the spin estimate off by 0.5 rad/s
    ctx = context_for(scene, [ep])
    h, g, _ = window_terms(sh, sigma, [w], drag, c, ctx)
    plain = c - np.linalg.solve(h[0], g[0])
    (hp, gp), = profiled_terms(sh, sigma, [w], drag, c, ctx)
    profiled = c - np.linalg.solve(hp, gp)
    assert abs(plain[0] - c[0]) > 0.02  # the slip reads as a different drag
    assert abs(profiled[0] - c[0]) < 0.25 * abs(plain[0] - c[0])


def _rolling_windows(c_true: float, dv: tuple[float, ...]):
    """A ball rolling along the floor (rolling resistance ``c_true`` in the recording, noise-free)
    and one window per entry of ``dv`` whose estimated start speed is that much too high (the
    spin kept on the rolling constraint), as noise in the start estimate makes it."""
    r = 0.1
    scene = SceneSpec((0.0, -9.81), (BodySpec("ball", "circle", mass=1.0, radius=r, friction=0.6, elasticity=0.5),),
                      (StaticSpec((-20.0, 0.0), (20.0, 0.0), 0.0, 1.0, 1.0),), ())
    rr = EffectSum((EFFECTS.get("rolling_resistance")(),))
    t = np.arange(301) / 100.0
    pose0, vel0 = np.array([[0.0, r, 0.0]]), np.array([[2.0, 0.0, -2.0 / r]])
    ep = simulate_episode(scene, 0, t, pose0, vel0, rr, np.array([c_true]), np.zeros((1, 3)), np.random.default_rng(0))
    sh = Shooter(scene, [ep], 1e-3, 5)
    wins = []
    for i, d in enumerate(dv):
        k0 = 20 + 60 * i
        pose, vel, sxx = sh.initial(0, k0)
        sh._ic[(0, k0)] = (pose, vel + np.array([[d, 0.0, -d / r]]), sxx)
        wins.append(Window(0, k0, k0 + 50))
    return sh, wins, rr, context_for(scene, [ep])


def test_a_hinge_fitted_to_start_speed_errors_is_not_kept_once_they_are_projected_out():
    """Like the clean cases 4497285 and 1829321: every window's start speed a little too high, so a
    small rolling resistance beats zero on the windows' plain errors and the fitting windows rule
    zero out; with the start velocities projected out nothing is left for it to explain."""
    sh, wins, rr, ctx = _rolling_windows(0.0, (0.02, 0.015, 0.02, 0.01))
    fit = np.array([0.003])
    plain = [window_sse(sh, wins, rr, np.array([c])).sum() for c in (0.0, 0.003)]
    assert plain[1] < 0.8 * plain[0]  # the hinge takes part of the start-speed error
    bases = velocity_bases(sh, wins, rr, fit)
    proj = [projected_sse(sh, wins, bases, rr, np.array([c])).sum() for c in (0.0, 0.003)]
    assert proj[0] < 1e-3 * plain[0] and proj[1] > proj[0]  # an error a start speed explains, and no hinge
    lo, hi = 0.0, 0.01  # a local interval that holds the nominal value 0
    assert nominal_side(sh, [wins], rr, fit, 0, ctx, lo, hi) != (lo, hi)  # plain: zero ruled out
    assert nominal_side(sh, [wins], rr, fit, 0, ctx, lo, hi, [bases]) == (lo, hi)


def test_a_true_rolling_resistance_survives_the_projection():
    sh, wins, rr, ctx = _rolling_windows(0.05, (0.02, -0.015, 0.0, 0.01))
    bases = velocity_bases(sh, wins, rr, np.array([0.05]))
    grid = np.linspace(0.0, 0.1, 21)
    proj = np.array([projected_sse(sh, wins, bases, rr, np.array([c])).sum() for c in grid])
    assert abs(grid[int(np.argmin(proj))] - 0.05) <= 0.005
    assert proj[0] > 100 * proj.min()  # zero is far worse once start speeds are allowed for
    assert nominal_side(sh, [wins], rr, np.array([0.05]), 0, ctx, 0.0, 0.1, [bases]) != (0.0, 0.1)
