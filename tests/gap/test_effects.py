"""Conformance of every registered effect, and composition with ``+``."""

from __future__ import annotations

import numpy as np
import pytest

from voe.errors import UnknownNameError
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum, FitContext
from voe.sim.scenefile import SimState

from .conftest import flight_scene

NAMES = EFFECTS.ids()  # every registered effect, so a new one is tested without editing this file


def _state() -> SimState:
    return SimState(np.array([[1.0, 2.0]]), np.array([[3.0, -4.0]]), np.array([0.3]), np.array([2.0]),
                    np.array([2.0]), np.array([0.01]), np.array([0.0, -9.81]), lambda: np.array([True]))


def _ctx() -> FitContext:
    return FitContext(flight_scene(), np.array([-1.0, 0.0]), np.array([1.0, 2.0]), 3.0, 2.0)


def test_registry_holds_the_library_and_none():
    assert "none" in NAMES and len(NAMES) >= 12


def test_typo_suggests_name():
    with pytest.raises(UnknownNameError, match="quadratic_drag"):
        EFFECTS.get("quadratic_drgа")


@pytest.mark.parametrize("name", NAMES)
def test_effect_conforms(name):
    eff = EFFECTS.get(name)()
    ctx = _ctx()
    scene = ctx.scene
    starts = eff.starts(ctx)
    lo, hi = eff.bounds(ctx)
    assert all(s.shape == (eff.n_params,) for s in starts)
    assert all(np.all(s >= lo) and np.all(s <= hi) for s in starts)
    assert eff.scale(ctx).shape == (eff.n_params,) and np.all(eff.scale(ctx) > 0)
    f, tau = eff.forces(_state(), starts[0], scene)
    assert f.shape == (1, 2) and tau.shape == (1,) and np.all(np.isfinite(f))
    eff.materials(starts[0], scene)
    nom = eff.nominal(ctx)
    assert nom.shape == (eff.n_params,)
    assert eff.acts in ("always", "contact", "region", "joint")
    if eff.bench_scene is not None:  # its bench prior draws parameters inside its bounds
        from voe.gap.bench import bench_scene

        bscene = bench_scene(eff.bench_scene, np.random.default_rng(0))
        p, bodies = eff.bench_prior(bscene, np.random.default_rng(1))
        assert p.shape == (eff.n_params,)
        assert bodies is None or set(bodies) <= set(bscene.names)
    with pytest.raises(ValueError, match=name):
        eff.forces(_state(), np.zeros(eff.n_params + 1), scene)


def test_force_laws_by_hand():
    st = _state()  # m = 2, v = (3, -4), |v| = 5, omega = 2
    scene = flight_scene()
    f, _ = EFFECTS.get("linear_drag")().forces(st, np.array([0.5]), scene)
    np.testing.assert_allclose(f, [[-3.0, 4.0]])  # -c m v
    f, _ = EFFECTS.get("quadratic_drag")().forces(st, np.array([0.1]), scene)
    np.testing.assert_allclose(f, [[-3.0, 4.0]])  # -c m |v| v = -0.1*2*5*v
    _, tau = EFFECTS.get("angular_damping")().forces(st, np.array([0.01]), scene)
    np.testing.assert_allclose(tau, [-0.02])
    f, _ = EFFECTS.get("spring_anchor")().forces(st, np.array([2.0, 0.0, 0.0]), scene)
    np.testing.assert_allclose(f, [[-4.0, -8.0]])  # -k m (r - p)


def test_plus_composes_parameters_and_forces():
    q, a = EFFECTS.get("quadratic_drag")(), EFFECTS.get("constant_acceleration")()
    combo = q + a + EFFECTS.get("restitution")()
    assert isinstance(combo, EffectSum)
    assert combo.n_params == 4
    assert combo.param_names[0] == "quadratic_drag.c"
    p = np.array([0.1, 1.0, 0.0, 0.3])
    f, _ = combo.forces(_state(), p, flight_scene())
    np.testing.assert_allclose(f, [[-3.0 + 2.0, 4.0]])
    assert combo.materials(p, flight_scene()).elasticity == (0.3,)
    assert "quadratic_drag" in combo.describe(p)
