"""Unchangeableness-v3: the object's shape and/or size changes at the onset, its path does not."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import balanced, main_slot
from voe.concepts import get_concept
from voe.sim.scene import FEATURE_NAMES, SimConfig

W, H, CIRCLE = (FEATURE_NAMES.index(f) for f in ("width", "height", "is_circle"))




@pytest.fixture(scope="module")
def sets():
    c = get_concept("Unchangeableness-v3")
    return [c.make_set(i, 0, SimConfig()) for i in range(6)]  # even: visible, odd: occluded


def test_all_kinds_of_change_occur(sets):
    more = [get_concept("unchangeableness").make_set(i, 1, SimConfig()) for i in range(6)]
    assert {m.params["change"] for m in sets + more} == {"shape", "size", "both"}


def test_look_changes_at_onset_path_does_not(sets):
    for m in sets:
        a, b, ab, ba = (cl.rec for cl in m.clips)
        slot, t0 = main_slot(a), m.params["splice_onset"]
        assert balanced(a, b, ab, ba)
        assert np.any(ab.frames[t0:] != a.frames[t0:])
        assert np.array_equal(ab.frames[:t0], a.frames[:t0])
        # same x trajectory in A and B wherever both are visible
        both = a.present[:, slot] & b.present[:, slot]
        assert both.sum() >= 10
        np.testing.assert_allclose(a.states[both, slot, 0], b.states[both, slot, 0], atol=1e-4)
        # AB: the last visible look before t0 is X's, the first visible look from t0 on is Y's
        pre = np.flatnonzero(ab.present[:t0, slot])[-1]
        post = t0 + np.flatnonzero(ab.present[t0:, slot])[0]
        before, after = ab.states[pre, slot], ab.states[post, slot]
        size_changed = abs(after[W] / before[W] - 1) > 0.25
        assert after[H] == pytest.approx(before[H])  # v2: same height, same resting y
        shape_changed = before[CIRCLE] != after[CIRCLE]
        change = m.params["change"]
        assert size_changed == (change in ("size", "both"))
        assert shape_changed == (change in ("shape", "both"))


def test_visible_vs_occluded_onsets(sets):
    for m in sets:
        a, b = m.clips[0].rec, m.clips[1].rec
        slot, t0 = main_slot(a), m.params["splice_onset"]
        if m.visible:  # both in plain view, clear of the screen, at t0 - 1 and t0
            x0, x1 = m.params["screen_x"] - m.params["screen_width"] / 2, m.params["screen_x"] + m.params["screen_width"] / 2
            for rec in (a, b):
                assert rec.present[t0 - 1:t0 + 1, slot].all()
                x, w = rec.states[t0, slot, 0], rec.states[t0, slot, W]
                assert x + w / 2 < x0 or x - w / 2 > x1
        else:  # both fully hidden at t0: their frames are identical there
            assert not a.present[t0, slot] and not b.present[t0, slot]
            assert np.array_equal(a.frames[t0], b.frames[t0])
            assert a.present[:t0, slot].any() and b.present[t0:, slot].any()
