"""Solidity-v2: each possible object bounces back off the wall; the spliced ones come out on the far side."""

from __future__ import annotations

import numpy as np
import pytest

from voe.concepts import get_concept
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, VX = FEATURE_NAMES.index("x"), FEATURE_NAMES.index("vx")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Solidity-v2")
    return [c.make_set(i, s, SimConfig()) for s in (0, 7) for i in range(8)]


def _seen_x(rec, slot, frames):
    t = frames[rec.present[frames, slot]]
    return rec.states[t, slot, X]


def test_possible_objects_stay_on_their_side_and_bounce(sets):
    for m in sets:
        slot, wx = m.params["main_slots"][0], m.params["wall_x"]
        a, b = (cl.rec for cl in m.clips[:2])
        T = np.arange(len(a))
        assert (_seen_x(a, slot, T) < wx).all() and (_seen_x(b, slot, T) > wx).all()
        assert a.states[0, slot, VX] > 0 and b.states[0, slot, VX] < 0
        assert (np.nan_to_num(a.states[:, slot, VX]) < 0).any()  # A comes back off the wall


def test_spliced_objects_come_out_on_the_far_side(sets):
    for m in sets:
        slot, wx, onset = m.params["main_slots"][0], m.params["wall_x"], m.clips[0].onset
        ab, ba = (cl.rec for cl in m.clips[2:])
        before, after = np.arange(onset), np.arange(onset, len(ab))
        assert (_seen_x(ab, slot, before) < wx).all() and (_seen_x(ab, slot, after) > wx).all()
        assert (_seen_x(ba, slot, before) > wx).all() and (_seen_x(ba, slot, after) < wx).all()
        assert _seen_x(ab, slot, after).size >= 3  # and is seen there


def test_occluded_splice_is_hidden_and_the_wall_top_stays_in_view(sets):
    assert {m.condition for m in sets} == {"occluded", "perceptual"}
    for m in sets:
        slot, onset = m.params["main_slots"][0], m.clips[0].onset
        if m.condition == "occluded":
            assert m.carries_verdict
            for cl in m.clips:
                assert not cl.rec.present[onset - 2:onset + 2, slot].any()
            occ = m.clips[0].rec.geometry["occluders"][0]
            assert m.params["wall_top"] > occ["y1"] + 0.5
        else:
            assert not m.carries_verdict and m.clips[0].rec.present[onset, slot]
