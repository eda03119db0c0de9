"""Energy-v1: the possible ball peaks below its drop height, the impossible one above it."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import assert_pair
from voe.concepts import get_concept
from voe.concepts.parts import FLOOR_Y
from voe.sim.scene import FEATURE_NAMES, SimConfig

Y, VY = FEATURE_NAMES.index("y"), FEATURE_NAMES.index("vy")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Energy-v1")
    return [c.make_set(i, s, SimConfig()) for s in (0, 1) for i in range(12)]


def _peak_after(rec, slot, onset, r):
    """Highest bottom height above the floor on the frames seen from the onset on."""
    y = rec.states[onset:, slot, Y]
    return float(np.nanmax(y)) - r - FLOOR_Y


def test_pair_shares_the_prefix_and_differs_after(sets):
    for m in sets:
        assert_pair(m, 5, 25)


def test_dropped_from_rest_and_onset_is_the_first_impact(sets):
    for m in sets:
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        pos = m.clips[0].rec
        r = p["look"]["height"] / 2
        assert pos.states[0, slot, Y] == pytest.approx(FLOOR_Y + r + p["drop"])
        assert pos.states[0, slot, VY] == 0.0
        seen = np.flatnonzero(pos.present[:onset, slot])
        assert (pos.states[seen, slot, VY] <= 0).all()  # falling the whole way to the impact


def test_possible_peaks_lower_and_impossible_higher_than_the_drop(sets):
    for m in sets:
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        r, h = p["look"]["height"] / 2, p["drop"]
        pos, imp = (cl.rec for cl in m.clips)
        assert _peak_after(pos, slot, onset, r) < 0.75 * h
        assert _peak_after(imp, slot, onset, r) > 1.2 * h
        assert _peak_after(imp, slot, onset, r) == pytest.approx(p["gain"] * h, rel=0.05)


def test_impact_hidden_in_occluded_sets(sets):
    for m in sets:
        imp, onset, slot = m.clips[1].rec, m.clips[0].onset, m.params["main_slots"][0]
        assert imp.present[onset, slot] == m.visible
