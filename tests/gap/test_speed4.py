"""Session 16's speed-ups (gapspeed4) give the same numbers as the code they replaced.

The references are the replaced code, kept here in its arithmetic: the force laws as the effects'
``_forces`` (the unprepared path ``Effect.forces`` still takes), ``inside`` edge by edge, and a
``SimWorld`` built through pymunk's property setters. A window taken from ``Shooter``'s memo is
the window simulated again. A changed bit fails.
"""

from __future__ import annotations

import numpy as np
import pymunk
import pytest

from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.region import inside, inside_at
from voe.gap.rollout import run_many, tiled
from voe.gap.shooting import Shooter, local_state, make_windows
from voe.gap.truths import Gust
from voe.sim.scenefile import _STATIC, Materials, SimState, SimWorld


def _state(rng: np.random.Generator, n: int) -> SimState:
    """A random state of ``n`` bodies over many orders of magnitude, some exact zeros."""
    mag = 10.0 ** rng.uniform(-6, 2, size=(n, 1))
    vel = rng.normal(size=(n, 2)) * mag
    vel[rng.random((n, 2)) < 0.1] = 0.0
    touch = rng.random(n) < 0.6
    return SimState(rng.normal(size=(n, 2)) * mag, vel, rng.normal(size=n), rng.normal(size=n) * (rng.random(n) < 0.9),
                    rng.uniform(0.1, 5, n), rng.uniform(0.01, 1, n), np.array([0.0, -9.81]), lambda: touch.copy())


def _same(a: np.ndarray, b: np.ndarray) -> None:
    """Equal to the bit, signs of zeros included; a NaN equals a NaN (its sign bit and payload
    mean nothing to any later operation: ``np.nan_to_num`` and every comparison see one NaN)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    nan = np.isnan(a)
    assert np.array_equal(nan, np.isnan(b))
    assert np.where(nan, 0.0, a).tobytes() == np.where(nan, 0.0, b).tobytes()


def test_inside_at_is_inside_to_the_bit():
    rng = np.random.default_rng(4)
    for trial in range(400):
        x0, x1 = sorted(rng.normal(size=2) * 2)
        n = int(rng.integers(1, 40))
        x = rng.normal(size=n) * 3
        x[rng.random(n) < 0.2] = x0  # exact edges
        x[rng.random(n) < 0.1] = x1
        x[rng.random(n) < 0.1] = x0 + 0.5  # clipped at 50 edge widths
        if trial % 4 == 0:
            x[0] = [np.nan, np.inf, -np.inf, 1e300][trial // 4 % 4]
        _same(inside_at(x0, x1)(x), inside(x, x0, x1))


@pytest.mark.parametrize("name", ["rolling_resistance_region", "rolling_resistance"])
@pytest.mark.parametrize("bodies", [None, ("ball",)])
def test_prepared_force_laws_are_their_forces_to_the_bit(name, bodies):
    """``prepare`` (what the rollouts call at every kick) against ``forces`` (``_forces`` and the
    body mask, the code the prepared laws replaced), on the scene tiled as ``run_many`` does."""
    scene = make_case(np.random.default_rng(5), "none", episodes=1, duration=0.5).scene
    eff = EFFECTS.get(name)(bodies)
    rng = np.random.default_rng(7)
    for trial in range(120):
        w = int(rng.integers(1, 9))
        big = tiled(scene, w)
        st = _state(rng, len(big.bodies))
        if trial % 5 == 0:
            st.pos[0, 0] = np.nan  # a diverged rollout
        p = np.array([rng.uniform(-1, 2), *sorted(rng.normal(size=2))])[:eff.n_params]
        if trial % 7 == 0:
            p[0] = 0.0
        force = eff.prepare(p, big)
        for _ in range(2):  # the prepared law keeps constants between calls
            f, tau = force(st)
            f_ref, tau_ref = eff.forces(st, p, big)
            _same(f, f_ref)
            _same(tau, tau_ref)
            st = SimState(st.pos + 0.01, -st.vel, st.angle, st.omega, st.mass, st.moment, st.gravity, st.contact)


def _old_world(scene, pose, vel, mat: Materials) -> SimWorld:
    """``SimWorld`` as built before session 16 (pymunk's property setters), without region handler."""
    w = SimWorld.__new__(SimWorld)
    w.scene = scene
    w.space = pymunk.Space()
    w.space.gravity = tuple(scene.gravity)
    w.bodies = []
    for i, spec in enumerate(scene.bodies):
        scale = mat.mass_scale[i] if mat.mass_scale else 1.0
        body = pymunk.Body(spec.mass * scale, spec.moment_value() * scale)
        body.position = (float(pose[i, 0]), float(pose[i, 1]))
        body.angle = float(pose[i, 2])
        body.velocity = (float(vel[i, 0]), float(vel[i, 1]))
        body.angular_velocity = float(vel[i, 2])
        if spec.shape == "circle":
            shape = pymunk.Circle(body, spec.radius)
        else:
            shape = pymunk.Poly(body, [tuple(v) for v in spec.local_vertices()])
        shape.friction = spec.friction if not mat.friction or mat.friction[i] is None else float(mat.friction[i])
        shape.elasticity = spec.elasticity if not mat.elasticity or mat.elasticity[i] is None else float(mat.elasticity[i])
        w.space.add(body, shape)
        w.bodies.append(body)
    for st in scene.statics:
        seg = pymunk.Segment(w.space.static_body, st.a, st.b, st.radius)
        seg.friction, seg.elasticity = st.friction, st.elasticity
        seg.collision_type = _STATIC
        w.space.add(seg)
    w._mass = np.array([b.mass for b in w.bodies])
    w._moment = np.array([b.moment for b in w.bodies])
    w._gravity = np.array(scene.gravity, dtype=float)
    return w


@pytest.mark.parametrize("mat", [Materials(), Materials((0.2, None), (None, 0.9), (1.3, 0.7))])
def test_simworld_built_by_c_setters_steps_as_built_by_pymunk_setters(mat):
    case = make_case(np.random.default_rng(5), "none", episodes=2, duration=2.0)
    t = case.episodes[0].t[:150]
    drag = EFFECTS.get("quadratic_drag")().prepare(np.array([0.1]), case.scene)
    for e in case.episodes:
        for k0 in (3, 70):
            pose0, vel0 = local_state(e, k0)[:2]
            old, new = _old_world(case.scene, pose0, vel0, mat), SimWorld(case.scene, pose0, vel0, mat)
            assert [b.position for b in new.bodies] == [b.position for b in old.bodies]
            _same(new.run(t, 1e-3, drag), old.run(t, 1e-3, drag))


def test_shooter_memo_gives_the_simulated_windows():
    case = make_case(np.random.default_rng(5), "quadratic_drag", episodes=3, duration=2.0)
    sh = Shooter(case.scene, case.episodes, 1e-3)
    wins = make_windows(case.episodes, [0, 1, 2], 1.0)
    eff = EFFECTS.get("quadratic_drag")() + EFFECTS.get("friction")()
    p = np.array([0.1, 0.3])

    def fresh(ws, e, q):
        return run_many(sh.scene, [sh.initial(w.ep, w.k0)[:2] for w in ws],
                        [sh.episodes[w.ep].t[w.k0:w.k1 + 1] for w in ws], sh.substep, e, q)

    first = sh.simulate_many(wins[:3], eff, p)
    first[0][:] = 0.0  # a caller's change does not reach the memo
    again = sh.simulate_many(wins[1:], eff, p)  # two remembered, the rest simulated
    assert sh.n_rollouts == 3 + len(wins) - 1 and sh.n_memo == 2
    for a, b in zip(again, fresh(wins[1:], eff, p), strict=True):
        _same(a, b)
    _same(sh.simulate(wins[0], eff, p), fresh(wins[:1], eff, p)[0])
    n = sh.n_memo
    other = sh.simulate_many(wins[:2], eff, np.array([0.1, 0.30000000000000004]))  # one bit off: simulated
    assert sh.n_memo == n
    _same(np.stack(other), np.stack(fresh(wins[:2], eff, np.array([0.1, 0.30000000000000004]))))
    bodies = EFFECTS.get("quadratic_drag")(("ball",)) + EFFECTS.get("friction")()  # other bodies: simulated
    sh.simulate_many(wins[:1], bodies, p)
    assert sh.n_memo == n
    gust = Gust()  # keeps state between calls: never remembered
    sh.simulate_many(wins[:1], gust, np.array([1.0, 1.0, 0.0]))
    sh.simulate_many(wins[:1], gust, np.array([1.0, 1.0, 0.0]))
    assert sh.n_memo == n
