"""Only mass ratios are seen when every force is mass-proportional: a round does not offer the
mass that would put one on every body (``voe.gap.mass_ratio``)."""

from __future__ import annotations

import numpy as np
import pytest

from voe.gap import search
from voe.gap.bench import bench_scene
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.effects.mass import Mass
from voe.gap.fit import FitResult
from voe.gap.mass_ratio import one_too_many
from voe.gap.synth import simulate_episode
from voe.sim.scenefile import BodySpec, SceneSpec

from .test_null_skip import W, _Fitter

PROPORTIONAL = [n for n in EFFECTS.ids() if EFFECTS.get(n).mass_proportional]
# effects without a bench prior (the region effects): a strength away from nominal over the box's first metre
REGION = {"friction_region": [2.0, 0.0, 1.0], "restitution_region": [0.9, -2.5, 1.0], "rolling_resistance_region": [0.2, 0.0, 1.0]}


def _motion(name: str, scale: float) -> np.ndarray:
    """(T, B, 3) poses of the bench arena (ball thrown at the box) under effect ``name`` at a bench
    draw of its parameters, every body's mass and moment scaled by ``scale``."""
    rng = np.random.default_rng(3)
    scene = bench_scene("arena", rng)
    cls = EFFECTS.get(name)
    p, bodies = (np.asarray(REGION[name], float), None) if name in REGION else \
        (np.zeros(0), None) if name == "none" else cls().bench_prior(scene, rng)
    eff = EffectSum((cls(bodies=bodies), Mass(bodies=tuple(scene.names))))
    pose0 = np.array([[-1.6, 0.6, 0.0], [0.1, 0.1, 0.0]])  # (B, 3) ball, box on the floor
    vel0 = np.array([[3.5, 1.5, 5.0], [0.5, 0.0, 0.0]])
    t = np.arange(151) / 100
    ep = simulate_episode(scene, 0, t, pose0, vel0, eff, np.concatenate([p, [scale]]), np.zeros((2, 3)), rng)
    return ep.pose


@pytest.mark.parametrize("name", PROPORTIONAL)
def test_a_mass_proportional_effect_moves_the_same_with_every_mass_scaled(name):
    """Every effect that declares ``mass_proportional`` is checked by simulation (a new one too):
    the ball strikes the box, the effect moves it away from the nominal motion, and every mass x2.5
    changes no pose by more than 1e-7."""
    a, b = _motion(name, 1.0), _motion(name, 2.5)
    assert np.ptp(a[:, 0, 0]) > 0.5  # the throw happens
    assert np.max(np.abs(a - _motion("none", 1.0))) > 1e-3  # and the effect acts in it
    np.testing.assert_allclose(b, a, atol=1e-7, rtol=0)


def test_the_check_can_fail_a_torque_that_does_not_scale_with_the_moment():
    """The control: ``angular_damping`` (a torque -b omega) is not mass-proportional, and the same
    simulation tells (so the test above would catch a false declaration)."""
    assert "angular_damping" not in PROPORTIONAL and {"mass", "rolling_resistance", "friction"} <= set(PROPORTIONAL)
    a, b = _motion("angular_damping", 1.0), _motion("angular_damping", 2.5)
    assert np.max(np.abs(b - a)) > 1e-3


def _scene(n: int) -> SceneSpec:
    return SceneSpec((0.0, -9.81), tuple(BodySpec(f"b{i}", "circle", mass=1.0, radius=0.1) for i in range(n)))


def test_one_mass_too_many_only_when_every_body_has_one_and_every_part_scales():
    two, three = _scene(2), _scene(3)
    m0, m1, m2 = (Mass(bodies=(f"b{i}",)) for i in range(3))
    rr, spin = EFFECTS.get("rolling_resistance")(), EFFECTS.get("angular_damping")()
    assert not one_too_many(two, (m0,)) and not one_too_many(two, (m0, rr))
    assert one_too_many(two, (m0, m1)) and one_too_many(two, (m0, rr, m1))
    assert not one_too_many(two, (m0, spin, m1))  # the torque sees the moments' absolute size
    assert not one_too_many(three, (m0, m1)) and one_too_many(three, (m0, m1, m2))
    assert one_too_many(two, (Mass(bodies=("b0", "b1")),)) and not one_too_many(_scene(1), (Mass(),))


def test_a_round_does_not_fit_the_mass_that_would_cover_every_body(no_stand_ins):
    """On top of ``mass[b0]``, round 2 fits ``rolling_resistance`` and leaves out ``mass[b1]``, which
    the made-up table makes the best gain (the test can fail); in the first round both masses are fitted."""
    fitter = _Fitter({"": np.ones(W)})
    fitter.scene = _scene(2)
    pool = {"mass[b1]": Mass(bodies=("b1",)), "rolling_resistance": EFFECTS.get("rolling_resistance")()}
    current = FitResult(EffectSum((Mass(bodies=("b0",)),)), np.ones(1), 0.0, 0.0, np.ones(W), (np.ones(1),))
    search.fit_rounds([search.RoundTask(fitter, pool, current, np.ones(W))])
    assert fitter.fitted == ["mass+rolling_resistance"]
    fitter.fitted = []
    search.fit_rounds([search.RoundTask(fitter, {**pool, "mass[b0]": Mass(bodies=("b0",))}, None, np.ones(W))])
    assert sorted(fitter.fitted) == ["mass", "mass", "rolling_resistance"]


def test_neither_a_later_round_nor_the_reselection_puts_a_mass_on_every_body(no_stand_ins, monkeypatch):
    """Round 1 names ``rolling_resistance``, round 2 ``mass[b0]``; a made-up table makes both masses
    together far better (as a re-spotted first mass would be), so without the rule round 3 adds
    ``mass[b1]`` and the re-selection would swap the rolling resistance for it. With it, neither."""
    from voe.gap import reselect
    from voe.gap.greedy import greedy

    from .test_reselect import _TableFitter

    class _ByBody(_TableFitter):  # keyed by repr, which names the body: mass[b0] and mass[b1] differ
        def _result(self, parts: tuple):
            from voe.gap.fit import FitResult

            eff = EffectSum(parts)
            return FitResult(eff, np.zeros(eff.n_params), 0.0, 0.0, self.table["+".join(sorted(map(repr, parts)))])

    w = np.linspace(0.8, 1.2, 20)  # (W,)
    table = {"": w, "rolling_resistance": 0.3 * w, "mass[b0]": 0.4 * w, "mass[b1]": 0.45 * w,
             "mass[b0]+rolling_resistance": 0.15 * w, "mass[b1]+rolling_resistance": 0.2 * w,
             "mass[b0]+mass[b1]": 0.01 * w, "mass[b0]+mass[b1]+rolling_resistance": 0.01 * w}

    def run():
        fitter = _ByBody(table)
        fitter.shooter.scene = _scene(2)
        cands = {"rolling_resistance": EFFECTS.get("rolling_resistance")(), "mass[b0]": Mass(bodies=("b0",)),
                 "mass[b1]": Mass(bodies=("b1",))}
        return greedy(fitter, cands, lambda r: 0.1, 3, set(), 1e-3)

    assert run().keys == ("rolling_resistance", "mass[b0]")
    with monkeypatch.context() as m:  # the rounds' rule alone: the re-selection swaps the rolling resistance out
        m.setattr(reselect, "not_offered", lambda fitter, parts: False)
        assert run().keys == ("mass[b1]", "mass[b0]")
    monkeypatch.setattr(search, "not_offered", lambda fitter, parts: False)  # the re-selection's alone: round 3
    assert run().keys == ("rolling_resistance", "mass[b0]", "mass[b1]")
