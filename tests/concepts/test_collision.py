"""Collision-v2: objects collide in the possible clip; pass through or act at a distance otherwise."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import assert_pair
from voe.concepts import get_concept
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, VX = FEATURE_NAMES.index("x"), FEATURE_NAMES.index("vx")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Collision-v2")
    return [c.make_set(i, s, SimConfig()) for s in (0, 1) for i in range(12)]


def _order(rec, p):
    """``d * (x2 - x1)`` on frames where both objects are seen: positive while 1 is behind 2."""
    s1, s2 = p["main_slots"]
    both = rec.present[:, s1] & rec.present[:, s2]
    return p["direction"] * (rec.states[both, s2, X] - rec.states[both, s1, X])


def test_the_two_objects_look_different_and_meet_head_on(sets):
    for m in sets:
        a, b = m.params["looks"]
        assert abs(a["intensity"] - b["intensity"]) > 0.15
        assert a["height"] == b["height"]  # centres at one height: a head-on hit
        if "box" in (a["shape"], b["shape"]):
            assert abs(a["width"] - b["width"]) > 0.2 or a["shape"] != b["shape"]


def test_the_hit_does_not_tip_anything(sets):
    A = FEATURE_NAMES.index("angle")
    for m in sets:
        pos = m.clips[0].rec
        for s in m.params["main_slots"]:
            assert np.nanmax(np.abs(pos.states[:, s, A])) < 1e-3


def test_modes_and_visibilities(sets):
    kinds = {(m.params["mode"], m.visible) for m in sets}
    assert kinds == {("pass", True), ("pass", False), ("distance", True)}


def test_pair_shares_the_prefix_and_differs_after(sets):
    for m in sets:
        assert_pair(m, 3, 32)


def test_possible_keeps_the_order_and_pass_through_reverses_it(sets):
    for m in sets:
        pos, imp = (cl.rec for cl in m.clips)
        assert (_order(pos, m.params) > 0).all()
        if m.params["mode"] == "pass" and m.visible:
            assert (_order(imp, m.params) < -0.5).any()


def _out(rec, p, i):
    """``(T,)`` object ``i`` is seen wholly out of the screen's far side."""
    d, s, w = p["direction"], p["main_slots"][i], p["looks"][i]["width"]
    far = p["screen"][1] if d > 0 else p["screen"][0]
    return rec.present[:, s] & (d * (rec.states[:, s, X] - far) > w / 2)


def test_occluded_pass_through_brings_object_1_out_on_the_far_side_first(sets):
    for m in (m for m in sets if not m.visible):
        p, onset = m.params, m.clips[0].onset
        pos, imp = (cl.rec for cl in m.clips)
        # impossible: object 1 comes out on the far side and object 2 never does
        assert _out(imp, p, 0).any() and not _out(imp, p, 1)[onset:].any()
        # possible: object 1 comes out there only after object 2 has
        if _out(pos, p, 0).any():
            assert _out(pos, p, 1)[: int(np.argmax(_out(pos, p, 0))) + 1].any()


def test_pass_through_leaves_the_resting_object_untouched(sets):
    for m in (m for m in sets if m.params["mode"] == "pass" and m.visible):
        s1, s2 = m.params["main_slots"]
        pos, imp = (cl.rec for cl in m.clips)
        assert np.ptp(imp.states[:, s2, X]) < 1e-4  # object 2 never moves
        assert np.nanmax(np.abs(pos.states[:, s2, VX])) > 0.5  # while the real hit sets it moving


def test_action_at_a_distance_starts_object_2_across_a_gap(sets):
    for m in (m for m in sets if m.params["mode"] == "distance"):
        p, onset = m.params, m.clips[0].onset
        s1, s2 = p["main_slots"]
        imp = m.clips[1].rec
        gap = abs(imp.states[onset, s2, X] - imp.states[onset, s1, X]) - (
            p["looks"][0]["width"] + p["looks"][1]["width"]) / 2
        assert gap > 0.4
        assert abs(imp.states[onset - 1, s2, VX]) < 1e-6 and abs(imp.states[onset, s2, VX]) > 0.5
        assert abs(imp.states[onset, s1, VX]) < 1e-6  # object 1 stops dead


def test_contact_is_hidden_in_occluded_sets(sets):
    for m in sets:
        imp, onset = m.clips[1].rec, m.clips[0].onset
        for slot in m.params["main_slots"]:
            assert imp.exists[onset, slot]
            assert imp.present[onset, slot] == m.visible
