"""Collision-v3: possible objects bounce apart; the spliced ones come out the other way round."""

from __future__ import annotations

import numpy as np
import pytest

from voe.concepts import get_concept
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, VX, A = (FEATURE_NAMES.index(n) for n in ("x", "vx", "angle"))


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Collision-v3")
    return [c.make_set(i, s, SimConfig()) for s in (0, 7) for i in range(8)]


def _order(rec, slots, frames):
    """``x2 - x1`` on the given frames where both objects are seen."""
    s1, s2 = slots
    t = frames[rec.present[frames, s1] & rec.present[frames, s2]]
    return rec.states[t, s2, X] - rec.states[t, s1, X]


def test_the_two_objects_look_different_and_meet_head_on(sets):
    for m in sets:
        a, b = m.params["looks"]
        assert abs(a["intensity"] - b["intensity"]) > 0.15 and a["height"] == b["height"]
        for cl in m.clips[:2]:
            for s in m.params["main_slots"]:
                assert np.nanmax(np.abs(cl.rec.states[:, s, A])) < 1e-3  # nothing tips


def test_possible_objects_keep_their_order_and_bounce_apart(sets):
    for m in sets:
        slots = m.params["main_slots"]
        a, b = (cl.rec for cl in m.clips[:2])
        T = np.arange(len(a))
        assert (_order(a, slots, T) > 0).all() and (_order(b, slots, T) < 0).all()
        assert a.states[-1, slots[0], VX] < 0 < a.states[-1, slots[1], VX]  # both bounced back


def test_spliced_objects_come_out_the_other_way_round(sets):
    for m in sets:
        slots, onset = m.params["main_slots"], m.clips[0].onset
        ab = m.clips[2].rec
        assert (_order(ab, slots, np.arange(onset)) > 0).all()
        after = _order(ab, slots, np.arange(onset, len(ab)))
        assert after.size >= 3 and (after < 0).all()


def test_occluded_splice_hides_both_objects(sets):
    for m in sets:
        if m.condition != "occluded":
            continue
        onset = m.clips[0].onset
        for cl in m.clips:
            assert not cl.rec.present[onset - 2:onset + 2][:, m.params["main_slots"]].any()
