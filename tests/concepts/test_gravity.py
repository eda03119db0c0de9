"""Gravity-v2: the possible object falls back and lands, the impossible one flies on straight."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import assert_pair
from voe.concepts import get_concept
from voe.concepts.parts import FLOOR_Y
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, Y = FEATURE_NAMES.index("x"), FEATURE_NAMES.index("y")
VX, VY = FEATURE_NAMES.index("vx"), FEATURE_NAMES.index("vy")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Gravity-v2")
    return [c.make_set(i, s, SimConfig()) for s in (0, 1) for i in range(12)]


def _after(rec, slot, onset):
    t = np.flatnonzero(rec.present[onset:, slot]) + onset
    return t, rec.states[t, slot, X], rec.states[t, slot, Y]


def test_pair_shares_the_prefix_and_differs_after(sets):
    for m in sets:
        assert_pair(m, 3, 32)


def test_possible_lands_and_impossible_flies_straight_at_its_own_velocity(sets):
    for m in sets:
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        h = p["look"]["height"]
        pos, imp = (cl.rec for cl in m.clips)
        assert pos.states[-1, slot, Y] == pytest.approx(FLOOR_Y + h / 2, abs=0.1)
        t, x, y = _after(imp, slot, onset)
        assert np.abs(np.diff(x, 2)).max() < 1e-3 and np.abs(np.diff(y, 2)).max() < 1e-3  # a straight line
        assert y.min() - h / 2 > FLOOR_Y + 1.0  # it never comes down
        # at the velocity it had when gravity went off: nothing but gravity is broken
        v = imp.states[t[0], slot, [VX, VY]]
        np.testing.assert_allclose(v, [p["vx"], p["vy"] - 9.81 * p["at"] * 0.05], atol=1e-3)
        assert abs(v[1]) < 1.0  # near the top of the arc: nearly level


def test_both_clips_show_the_object_on_the_same_frames(sets):
    for m in sets:
        slot = m.params["main_slots"][0]
        pos, imp = (cl.rec for cl in m.clips)
        np.testing.assert_array_equal(pos.present[:, slot], imp.present[:, slot])
        assert pos.present[:3, slot].all()  # seen before it goes behind anything


def test_gravity_goes_off_behind_the_pillar_in_occluded_sets(sets):
    assert {m.visible for m in sets} == {True, False}
    for m in sets:
        imp, onset, slot = m.clips[1].rec, m.clips[0].onset, m.params["main_slots"][0]
        assert imp.present[onset - 1:onset + 1, slot].tolist() == [m.visible] * 2
