"""The speed-ups of sessions 11 and 12 (gap_speed) give the same numbers as the code they replaced.

Each reference below is the replaced implementation, kept here verbatim in its arithmetic: the
restitution pre-solve callback registered through pymunk's ``Space.on_collision`` with pymunk's
getters, the substep schedule as ``SimWorld.run``'s Python loop, and ``Fitter.focused``'s screen
one window at a time, and the force laws' norms and clips as written before session 12. A
changed bit, window or rollout count fails.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
import pytest
from pymunk._chipmunk import ffi, lib

from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.fit import Fitter
from voe.gap.shooting import Shooter, local_state, make_windows, noise_floor
from voe.gap.stages import context_for
from voe.sim.lockstep import schedule
from voe.sim.scenefile import _STATIC, Materials, SimState, SimWorld


def _pymunk_pre(e: float, x0: float, x1: float, get=lib.cpShapeGetElasticity, put=lib.cpArbiterSetRestitution):
    """The pre-solve callback as it was before (through pymunk's dispatcher and Arbiter); with
    ``get``/``put`` of friction, the reference of the region friction set the same way."""
    seg_p, other_p = ffi.new("cpShape *[1]"), ffi.new("cpShape *[1]")

    def pre(arb: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        a = arb._arbiter  # noqa: SLF001
        if not lib.cpArbiterGetCount(a):
            return
        lib.cpArbiterGetShapes(a, seg_p, other_p)
        x = lib.cpArbiterGetContactPointSet(a).points[0].pointA.x
        w = 1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, (x - x0) / 0.01))))
        w /= 1.0 + math.exp(-max(-50.0, min(50.0, (x1 - x) / 0.01)))
        seg_e = get(seg_p[0])
        put(a, get(other_p[0]) * (seg_e + w * (e - seg_e)))

    return pre


@pytest.fixture(scope="module")
def arena():
    """An arena case (ball thrown at a box on the floor: bounces, resting and sliding contacts)."""
    case = make_case(np.random.default_rng(5), "none", episodes=2, duration=2.0)
    starts = [local_state(e, k0)[:2] for e in case.episodes for k0 in (3, 70, 140)]
    return case, starts


REGIONS = [("elasticity", r) for r in [(0.2, -1.0, 1.0), (0.9, -0.3, 0.05), (0.0, -8.0, 8.0), (0.6, 5.0, 6.0)]] + \
    [("friction", r) for r in [(3.0, -1.0, 1.0), (0.1, -0.3, 0.6), (2.5, 5.0, 6.0)]]


@pytest.mark.parametrize(("kind", "region"), REGIONS)
def test_region_callback_is_bit_for_bit_the_pymunk_one(arena, kind, region):
    case, starts = arena
    t = case.episodes[0].t[:120]
    mats = Materials(region_elasticity=region) if kind == "elasticity" else Materials(region_friction=region)
    ref = (lib.cpShapeGetElasticity, lib.cpArbiterSetRestitution) if kind == "elasticity" else \
        (lib.cpShapeGetFriction, lib.cpArbiterSetFriction)
    for pose0, vel0 in starts:
        fast = SimWorld(case.scene, pose0, vel0, mats)
        slow = SimWorld(case.scene, pose0, vel0)
        slow.space.on_collision(_STATIC, None, pre_solve=_pymunk_pre(*region, *ref))
        np.testing.assert_array_equal(fast.run(t, 1e-3), slow.run(t, 1e-3))
    plain = SimWorld(case.scene, *starts[0]).run(t, 1e-3)
    if region[1] < 5.0:  # the patch is where the bodies bounce and slide: the callback acts
        assert not np.array_equal(SimWorld(case.scene, *starts[0], mats).run(t, 1e-3), plain)
    if kind == "friction":  # with a restitution patch where no body touches, as with the friction alone
        both = Materials(region_elasticity=(0.5, 7.0, 7.5), region_friction=region)
        np.testing.assert_array_equal(SimWorld(case.scene, *starts[0], both).run(t, 1e-3),
                                      SimWorld(case.scene, *starts[0], mats).run(t, 1e-3))


def _schedule_loop(times: np.ndarray, substep: float) -> tuple[list[float], list[int]]:
    """The substeps as ``SimWorld.run``'s loop takes them."""
    h: list[float] = []
    ends: list[int] = []
    for dt in np.diff(times).tolist():
        n = max(1, round(dt / substep))
        h.extend([dt / n] * n)
        ends.append(len(h))
    return h, ends


def test_schedule_is_the_loop_of_simworld_run():
    rng = np.random.default_rng(0)
    for trial in range(400):
        n = int(rng.integers(2, 80))
        t = [np.arange(n) * 0.01 + rng.uniform(0, 5),  # 100 Hz, float steps differ in the last bits
             np.cumsum(np.r_[rng.uniform(0, 3), rng.uniform(0.008, 0.012, n - 1)]),  # jittered
             np.cumsum(np.r_[0.0, rng.choice([5e-4, 1.5e-3, 2.5e-3, 1e-3, 1e-5], n - 1)])][trial % 3]  # half-way cases
        for sub in (1e-3, 5e-4):
            h, ends = schedule(t, sub)
            want_h, want_ends = _schedule_loop(t, sub)
            assert list(ends) == want_ends
            assert list(h) == want_h and all(type(x) is float for x in h)
    h1 = schedule(np.arange(5) * 0.01, 1e-3)[0]
    assert schedule(np.arange(5) * 0.01, 1e-3)[0] is h1  # remembered, and immutable
    assert isinstance(h1, tuple)


def _focused_one_by_one(fitter: Fitter, effect, x0, lo, hi, scale) -> list:
    """``Fitter.focused``'s screen as it was: one window at a time, stopping at the budget."""
    new = effect.parts[-1]
    n = new.n_params
    probe = x0.copy()
    probe[-n:] = np.clip(x0[-n:] + 3 * scale[-n:], lo[-n:], hi[-n:])
    if np.allclose(probe, x0):
        probe[-n:] = np.clip(x0[-n:] - 3 * scale[-n:], lo[-n:], hi[-n:])
    tol2 = (float(np.min(fitter.sigma[:, :2])) / 3) ** 2
    sh, hit = fitter.shooter, []
    for i in np.random.default_rng(len(fitter.pool)).permutation(len(fitter.pool)):
        w = fitter.pool[i]
        if not new.may_act(sh.scene, sh.episodes[w.ep].pose[w.k0:w.k1 + 1]):
            continue
        moved = float(np.nanmean((sh.residual(w, effect, probe) - sh.residual(w, effect, x0)) ** 2))
        if not np.isfinite(moved) or moved > tol2:
            hit.append(w)
            if len(hit) == len(fitter.train):
                break
    return sorted(hit, key=lambda w: (w.ep, w.k0))


@pytest.mark.parametrize("every", [5, 12])
def test_focused_screen_in_batches_picks_and_simulates_the_same_windows(every):
    case = make_case(np.random.default_rng(32), "mass")  # the box is heavier: a sparse effect
    eps, scene = case.episodes, case.scene
    sh = Shooter(scene, eps, 1e-3, 7)
    pool = make_windows(eps, list(range(8)), 1.0, stride=0.5)
    fitter = Fitter(sh, noise_floor(eps), pool[::every], make_windows(eps, [8], 1.0), context_for(scene, eps[:8]),
                    pool=pool)
    eff = EFFECTS.get("mass")(bodies=("box",))
    lo, hi = eff.bounds(fitter.ctx)
    args = (eff, np.array([1.0]), lo, hi, eff.scale(fitter.ctx))
    n0 = sh.n_rollouts
    want = _focused_one_by_one(fitter, *args)
    n_one = sh.n_rollouts - n0
    got = fitter.focused(*args)
    assert got.train == want and want  # the same windows, in the same order
    assert sh.n_rollouts - n0 - n_one == n_one  # and exactly as many rollouts


def _state(rng: np.random.Generator, n: int) -> SimState:
    """A random state of ``n`` bodies, speeds and positions over many orders of magnitude."""
    mag = 10.0 ** rng.uniform(-6, 4, size=(n, 1))
    return SimState(rng.normal(size=(n, 2)) * mag, rng.normal(size=(n, 2)) * mag, rng.normal(size=n), rng.normal(size=n),
                    rng.uniform(0.1, 5, n), rng.uniform(0.01, 1, n), np.array([0.0, -9.81]),
                    lambda: rng.random(n) < 0.5)


def test_cheaper_force_laws_give_the_textbook_formulas_to_the_bit():
    """Session 12: drag, rolling resistance and the attractor compute norms by ``np.add.reduce``,
    region edges clip by ``np.minimum``/``np.maximum``; the replaced expressions are the references."""
    from voe.gap.effects.point_attractor import _SOFT, PointAttractor
    from voe.gap.effects.quadratic_drag import QuadraticDrag
    from voe.gap.effects.region import inside
    from voe.gap.effects.rolling_resistance import _V0, RollingResistance

    rng = np.random.default_rng(12)
    for trial in range(300):
        st = _state(rng, int(rng.integers(1, 40)))
        p = np.array([rng.uniform(0, 2), rng.normal(), rng.normal()])
        speed = np.linalg.norm(st.vel, axis=1, keepdims=True)
        np.testing.assert_array_equal(QuadraticDrag()._forces(st, p[:1])[0], -p[0] * st.mass[:, None] * speed * st.vel)
        touch = np.random.default_rng(trial).random(len(st.mass)) < 0.5
        st.contact = lambda t=touch: t
        g = float(np.linalg.norm(st.gravity))
        want = -p[0] * g * (st.mass * touch.astype(float))[:, None] * st.vel / np.sqrt(speed**2 + _V0**2)
        np.testing.assert_array_equal(RollingResistance()._forces(st, p[:1])[0], want)
        d = p[None, 1:3] - st.pos
        want = st.mass[:, None] * p[0] * d / (np.sum(d**2, axis=1, keepdims=True) + _SOFT**2) ** 1.5
        np.testing.assert_array_equal(PointAttractor()._forces(st, p)[0], want)
        x = st.pos[:, 0].copy()
        if trial % 3 == 0:
            x[0] = np.nan  # a diverged rollout stays NaN, as with np.clip
        a, b = np.clip((x - p[1]) / 0.01, -50, 50), np.clip((p[2] - x) / 0.01, -50, 50)
        np.testing.assert_array_equal(inside(x, p[1], p[2]), 1.0 / (1.0 + np.exp(-a)) / (1.0 + np.exp(-b)))
