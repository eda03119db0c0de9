"""Windows a floor patch cannot touch are given their patchless poses (``voe.gap.bare``), which are
exactly what simulating them with the patch gives: checked over every registered effect that sets
a material per contact, at patches near and far from where the windows touch the floor."""

from __future__ import annotations

import numpy as np
import pytest

from voe.gap.bare import Bare, bare_params
from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.rollout import run_many, run_many_recorded
from voe.gap.shooting import Shooter, Window
from voe.gap.stages import context_for
from voe.sim.scenefile import Materials, SimWorld, region_inert


@pytest.fixture(scope="module")
def arena():
    """An arena case (ball thrown at a box on the floor: flight, bounces, sliding) and its windows."""
    case = make_case(np.random.default_rng(1), "none", episodes=3, duration=2.0)
    wins = [Window(ep, k0, k0 + 60) for ep in range(3) for k0 in (0, 50, 100, 139)]
    return case, wins


def _per_contact(case):
    """Every registered effect that sets a material per contact (a patch) on the case's scene."""
    ctx = context_for(case.scene, case.episodes)
    out = []
    for name in EFFECTS.ids():
        e = EFFECTS.get(name)()
        if e.applies(case.scene):
            m = e.materials(e.starts(ctx)[0], case.scene)
            if m.region_friction is not None or m.region_elasticity is not None:
                out.append(name)
    return out


def test_the_library_has_per_contact_patches(arena):
    case, _ = arena
    assert {"friction_region", "restitution_region"} <= set(_per_contact(case))


@pytest.mark.parametrize("with_drag", [False, True])
def test_every_patch_gives_the_patchless_poses_only_where_it_cannot_act(arena, with_drag):
    """For each per-contact patch, intervals across the arena (and beyond it), strong and weak:
    a window judged inert has exactly the poses of a rollout with the patch, and both kinds of
    window occur (so the check can fail either way)."""
    case, wins = arena
    ctx = context_for(case.scene, case.episodes)
    sh = Shooter(case.scene, case.episodes, 1e-3)
    starts, times = sh.starts_times(wins)
    reused = simulated = 0
    for name in _per_contact(case):
        patch = EFFECTS.get(name)()
        eff = EffectSum((EFFECTS.get("quadratic_drag")(), patch)) if with_drag else patch
        head = np.array([0.05]) if with_drag else np.zeros(0)
        lo, hi = float(ctx.lo[0]), float(ctx.hi[0])
        for strength in (0.1, 0.9):
            for a in np.linspace(lo - 0.5, hi, 7):
                p = np.concatenate([head, [strength, a, a + 0.6]])
                bare, contacts, mats = run_many_recorded(case.scene, starts, times, 1e-3, eff, p)
                full = run_many(case.scene, starts, times, 1e-3, eff, p)
                for b, c, f in zip(bare, contacts, full, strict=True):
                    if region_inert(c, mats):
                        np.testing.assert_array_equal(b, f, err_msg=f"{name} at {p}")
                        reused += 1
                    else:
                        simulated += 1
    assert reused > 20 and simulated > 20


def test_a_shooter_gives_the_same_poses_with_and_without_the_patchless_shortcut(arena):
    """A start screen's pattern (one model, many patches): the second patch on makes the patchless
    rollouts, reuses some windows, and every pose equals a plain rollout's."""
    case, wins = arena
    ctx = context_for(case.scene, case.episodes)
    eff = EFFECTS.get("friction_region")()
    sh = Shooter(case.scene, case.episodes, 1e-3)
    for p in eff.starts(ctx)[:12]:
        got = sh.simulate_many(wins, eff, p)
        for g, want in zip(got, run_many(case.scene, *sh.starts_times(wins), 1e-3, eff, p), strict=True):
            np.testing.assert_array_equal(g, want)
    assert sh.bare.n_reused > 0


def test_bare_params_blanks_only_the_patch():
    case = make_case(np.random.default_rng(1), "none", episodes=1, duration=0.5)
    eff = EffectSum((EFFECTS.get("quadratic_drag")(), EFFECTS.get("restitution_region")()))
    p = bare_params(eff, np.array([0.1, 0.3, 1.0, 2.0]), case.scene)
    assert p[0] == 0.1 and np.isnan(p[1:]).all()
    assert bare_params(EFFECTS.get("quadratic_drag")(), np.array([0.1]), case.scene) is None
    assert bare_params(EFFECTS.get("rolling_resistance_region")(), np.array([0.1, 1.0, 2.0]), case.scene) is None
    assert bare_params(None, None, case.scene) is None


def test_inert_needs_every_contact_far_and_a_grippy_floor():
    far = np.array([[5.0, 0.8, 0.5], [6.0, 0.8, 0.5]])  # (N, 3) x, segment friction, elasticity
    assert region_inert(far, Materials(region_friction=(2.0, 0.0, 1.0)))
    assert not region_inert(far, Materials(region_friction=(2.0, 4.0, 5.5)))  # a contact inside
    assert not region_inert(far, Materials(region_friction=(2.0, 5.3, 5.5)))  # 0.3 m off: the edge still acts
    assert region_inert(far, Materials(region_friction=(2.0, 5.4, 5.6)))  # 0.4 m from each: below the last bit
    bare_floor = far.copy()
    bare_floor[:, 1] = 0.0
    assert not region_inert(bare_floor, Materials(region_friction=(2.0, 0.0, 1.0)))  # 0 + w * u is not 0
    assert region_inert(np.zeros((0, 3)), Materials(region_elasticity=(0.1, 0.0, 1.0)))  # no contact at all
    nan = far.copy()
    nan[0, 0] = np.nan
    assert not region_inert(nan, Materials(region_elasticity=(0.1, 0.0, 1.0)))


def test_contacts_are_recorded_only_without_a_patch(arena):
    case, _ = arena
    pose, vel = np.zeros((2, 3)), np.zeros((2, 3))
    with pytest.raises(ValueError, match="only without region materials"):
        SimWorld(case.scene, pose, vel, Materials(region_friction=(1.0, 0.0, 1.0)), contacts=[])


def test_a_fresh_bare_makes_no_patchless_rollout_for_a_model_met_once(arena):
    case, wins = arena
    sh = Shooter(case.scene, case.episodes, 1e-3)
    b = Bare()
    eff = EFFECTS.get("friction_region")()
    b.simulate(sh, wins, eff, np.array([0.5, 0.0, 1.0]), ("k", (3,), b"x"))
    assert not b.memo
    b.simulate(sh, wins, eff, np.array([0.9, 2.0, 3.0]), ("k", (3,), b"y"))
    assert len(b.memo) == len(wins)


def test_a_full_memo_does_not_lose_the_windows_a_call_found_in_it(arena, monkeypatch):
    """Seed 9260's untouched run crashed on floor patch 9260144 (``KeyError`` in this memo): a call
    found some windows in the memo, inserted the ones it lacked, trimmed the memo to its size, which
    dropped the oldest entries (windows of the same call), and then read them."""
    import voe.gap.bare as bare
    monkeypatch.setattr(bare, "MEMO", 14)
    case, wins = arena
    sh = Shooter(case.scene, case.episodes, 1e-3)
    eff = EFFECTS.get("friction_region")()
    b = Bare()
    b.simulate(sh, wins, eff, np.array([0.5, 0.0, 1.0]), ("k", (3,), b"x"))  # seen: plain rollouts
    b.simulate(sh, wins, eff, np.array([0.9, 2.0, 3.0]), ("k", (3,), b"y"))  # the 12 patchless windows
    more = wins + [Window(ep, 20, 80) for ep in range(3)] + [Window(0, 30, 90)]  # 4 new: 16 > 14
    p = np.array([0.7, -1.0, 0.5])
    got = b.simulate(sh, more, eff, p, ("k", (3,), b"z"))
    assert len(b.memo) == 14
    for g, want in zip(got, run_many(case.scene, *sh.starts_times(more), 1e-3, eff, p), strict=True):
        np.testing.assert_array_equal(g, want)
