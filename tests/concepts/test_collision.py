"""Collision-v4: the objects always bounce apart, each to its own side; the splices only change when."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.timeshift import assert_time_shifted_occluded_sets
from voe.concepts import get_concept
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, VX, A = (FEATURE_NAMES.index(n) for n in ("x", "vx", "angle"))


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Collision-v4")
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


def test_every_clip_keeps_the_order_and_both_objects_bounce_apart(sets):
    for m in sets:
        slots = m.params["main_slots"]
        for cl in m.clips:
            assert (_order(cl.rec, slots, np.arange(len(cl.rec))) > 0).all()
        for cl in m.clips[:2]:
            assert cl.rec.states[-1, slots[0], VX] < 0 < cl.rec.states[-1, slots[1], VX]


def test_occluded_splices_come_back_late_or_early_at_the_same_places_and_speeds(sets):
    assert_time_shifted_occluded_sets(sets)


def test_occluded_splice_hides_both_objects(sets):
    for m in sets:
        if m.condition != "occluded":
            continue
        onset = m.clips[0].onset
        for cl in m.clips:
            assert not cl.rec.present[onset - 2:onset + 2][:, m.params["main_slots"]].any()
