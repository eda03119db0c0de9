"""Continuity-v2: the object is never seen crossing the gap in AB, and the splice is balanced."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import balanced, main_slot
from voe.concepts import get_concept
from voe.concepts.continuity import in_gap_frames
from voe.sim.scene import SimConfig


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Continuity-v2")
    return [c.make_set(i, 0, SimConfig()) for i in range(4)]  # visible, occluded, visible, occluded


def test_registered_and_deterministic(sets):
    again = get_concept("continuity").make_set(1, 0, SimConfig())
    assert np.array_equal(again.clips[2].rec.frames, sets[1].clips[2].rec.frames)
    assert again.params == sets[1].params


def test_teleport_in_ab_and_balance(sets):
    for m in sets:
        a, b, ab, ba = (cl.rec for cl in m.clips)
        assert [cl.variant for cl in m.clips] == ["A", "B", "AB", "BA"]
        slot = main_slot(a)
        assert not b.exists[:, slot].any()
        t1 = m.params["splice_onset"]
        differs = np.any(ab.exists != a.exists, axis=1)  # (T,)
        t2 = int(np.flatnonzero(differs).max()) + 1  # the mask is exactly [t1, t2)
        assert np.flatnonzero(differs).min() == t1 and t2 - t1 >= 2
        # AB: the object does not exist anywhere in [t1, t2), while in A it crosses the gap there
        assert not ab.exists[t1:t2, slot].any()
        assert a.present[t1:t2, slot].any()
        assert np.intersect1d(in_gap_frames(a, slot, m.params), np.arange(t1, t2)).size >= 1
        # ... and AB shows the object before t1 and after t2 (it comes out of screen 2)
        assert ab.present[:t1, slot].any() and ab.present[t2:, slot].any()
        # BA: the object exists only in [t1, t2)
        assert ba.exists[t1:t2, slot].all() and not ba.exists[:t1, slot].any()
        assert not ba.exists[t2:, slot].any()
        assert balanced(a, b, ab, ba)
        assert np.any(ab.frames[t1:t2] != a.frames[t1:t2])


def test_visible_vs_occluded_onsets(sets):
    for m in sets:
        a, b = m.clips[0].rec, m.clips[1].rec
        slot = main_slot(a)
        t1 = m.params["splice_onset"]
        t2 = int(np.flatnonzero(np.any(m.clips[2].rec.exists != a.exists, axis=1)).max()) + 1
        gap = in_gap_frames(a, slot, m.params)
        if m.visible:  # vanishes and reappears fully in view inside the gap
            assert t1 in gap and t2 in gap
        else:  # the switches happen behind the screens: no object pixel at t1 or t2
            assert not a.present[t1, slot] and not a.present[t2, slot]
            assert np.array_equal(a.frames[t1], b.frames[t1])
            assert np.array_equal(a.frames[t2], b.frames[t2])
            x = m.params["x0"] + m.params["direction"] * m.params["speed"] * np.array([t1, t2]) * SimConfig().dt
            sx1, sx2 = m.params["screen_x"]
            assert abs(x[0] - sx1) < abs(x[0] - sx2) and abs(x[1] - sx2) < abs(x[1] - sx1)
