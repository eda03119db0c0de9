"""Solidity-v1: the possible object stops at the shelf / wall, the impossible one goes through."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import assert_pair
from voe.concepts import get_concept
from voe.concepts.parts import FLOOR_Y
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, Y = FEATURE_NAMES.index("x"), FEATURE_NAMES.index("y")
BAR_R = 0.1


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Solidity-v1")
    return [c.make_set(i, s, SimConfig()) for s in (0, 1) for i in range(12)]


def _after(rec, slot, onset):
    """x, y of ``slot`` on the present frames from the onset on."""
    t = np.flatnonzero(rec.present[onset:, slot]) + onset
    return rec.states[t, slot, X], rec.states[t, slot, Y]


def test_both_events_and_both_visibilities_occur(sets):
    assert {(m.params["event"], m.visible) for m in sets} == {
        ("shelf", True), ("shelf", False), ("wall", True), ("wall", False)}


def test_pair_shares_the_prefix_and_differs_after(sets):
    for m in sets:
        assert_pair(m, 3, 30)


def test_shelf_holds_the_possible_object_and_not_the_impossible_one(sets):
    for m in (m for m in sets if m.params["event"] == "shelf"):
        p, slot = m.params, m.params["main_slots"][0]
        h, top, (x0, x1) = p["look"]["height"], p["shelf_y"] + BAR_R, p["shelf_x"]
        pos, imp = (cl.rec for cl in m.clips)
        _, y = _after(pos, slot, m.clips[0].onset)
        assert (y > top).all()  # never below the shelf's top
        if m.visible:  # it rests on the shelf at the end
            assert y[-1] == pytest.approx(top + h / 2, abs=0.15)
        x, y = _after(imp, slot, m.clips[0].onset)
        below = (y + h / 2 < p["shelf_y"] - BAR_R) & (x > x0) & (x < x1)
        assert below.any()  # wholly under the shelf, within its span: it went through
        assert y[-1] == pytest.approx(FLOOR_Y + h / 2, abs=0.15)  # and lies on the floor


def test_wall_stops_the_possible_object_and_not_the_impossible_one(sets):
    for m in (m for m in sets if m.params["event"] == "wall"):
        p, slot = m.params, m.params["main_slots"][0]
        d, w = p["direction"], p["look"]["width"]
        pos, imp = (cl.rec for cl in m.clips)
        x, _ = _after(pos, slot, 0)
        assert (d * (x - p["wall_x"]) < 0).all()  # stays on the near side
        x, _ = _after(imp, slot, m.clips[0].onset)
        assert (d * (x - p["wall_x"]) > w / 2 + BAR_R).any()  # wholly on the far side


def test_contact_is_hidden_in_occluded_sets_and_seen_in_visible_ones(sets):
    for m in sets:
        imp, onset, slot = m.clips[1].rec, m.clips[0].onset, m.params["main_slots"][0]
        assert imp.exists[onset, slot]
        assert imp.present[onset, slot] == m.visible
