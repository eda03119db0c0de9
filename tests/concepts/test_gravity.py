"""Gravity-v1: the possible object falls when unsupported, the impossible one floats."""

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
    c = get_concept("Gravity-v1")
    return [c.make_set(i, s, SimConfig()) for s in (0, 1) for i in range(12)]


def _after(rec, slot, onset):
    t = np.flatnonzero(rec.present[onset:, slot]) + onset
    return t, rec.states[t, slot, X], rec.states[t, slot, Y]


def test_events_and_visibilities(sets):
    kinds = {(m.params["event"], m.visible) for m in sets}
    assert {("ledge", True), ("ledge", False), ("throw", True)} <= kinds
    assert ("throw", False) not in kinds  # the throw is a visible-only event


def test_pair_shares_the_prefix_and_differs_after(sets):
    for m in sets:
        assert_pair(m, 3, 32)


def test_off_the_ledge_the_possible_falls_and_the_impossible_stays_level(sets):
    for m in (m for m in sets if m.params["event"] == "ledge"):
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        d, w, h = p["direction"], p["look"]["width"], p["look"]["height"]
        end = p["shelf_x"][1] if d > 0 else p["shelf_x"][0]
        rest = p["shelf_y"] + BAR_R + h / 2
        pos, imp = (cl.rec for cl in m.clips)
        _, x, y = _after(imp, slot, onset)
        off = d * (x - end) > w / 2 + 0.3  # clear of the shelf: nothing holds it up
        assert off.any()
        assert (y[off] > rest - 0.15).all()  # still at shelf height (or higher)
        _, x, y = _after(pos, slot, onset)
        off = d * (x - end) > w / 2 + 0.3
        assert off.any() and y[off].min() < rest - 1.0  # it fell


def test_thrown_object_lands_in_the_possible_and_hangs_or_rises_in_the_impossible(sets):
    for m in (m for m in sets if m.params["event"] == "throw"):
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        h = p["look"]["height"]
        pos, imp = (cl.rec for cl in m.clips)
        assert pos.states[-1, slot, Y] == pytest.approx(FLOOR_Y + h / 2, abs=0.1)
        _, x, y = _after(imp, slot, onset)
        assert np.ptp(x) < 1e-3  # it stops where it was
        assert (np.diff(y) > -1e-4).all()  # and never comes down
        assert y[-1] - h / 2 > FLOOR_Y + 0.8


def test_leaving_support_is_hidden_in_occluded_sets(sets):
    for m in sets:
        imp, onset, slot = m.clips[1].rec, m.clips[0].onset, m.params["main_slots"][0]
        assert imp.exists[onset, slot]
        assert imp.present[onset, slot] == m.visible
