"""Energy-v3: the impossible clip is the possible one played backwards; only its bounce gains energy."""

from __future__ import annotations

import numpy as np
import pytest

from voe.concepts import get_concept
from voe.concepts.parts import FLOOR_Y
from voe.sim.scene import FEATURE_NAMES, SimConfig

Y, VY = FEATURE_NAMES.index("y"), FEATURE_NAMES.index("vy")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Energy-v3")
    return [c.make_set(i, s, SimConfig()) for s in (0, 7) for i in range(8)]


def test_impossible_is_the_possible_clip_reversed(sets):
    for m in sets:
        pos, imp = (cl.rec for cl in m.clips)
        np.testing.assert_array_equal(imp.frames, pos.frames[::-1])
        np.testing.assert_array_equal(imp.states[..., Y], pos.states[::-1, :, Y])
        np.testing.assert_array_equal(imp.states[..., VY], -pos.states[::-1, :, VY])


def test_one_bounce_that_loses_energy_forwards_and_gains_it_backwards(sets):
    for m in (m for m in sets if m.condition == "visible"):
        slot, onset, T = m.params["main_slots"][0], m.clips[0].onset, SimConfig().n_frames
        h = m.params["look"]["height"]
        pos, imp = (cl.rec for cl in m.clips)
        vy = pos.states[:, slot, VY]
        assert (np.diff(np.sign(vy)) > 0).sum() == 1  # one bounce
        impact = T - onset
        top_before = pos.states[:impact, slot, Y].max() - h / 2 - FLOOR_Y
        top_after = pos.states[impact:, slot, Y].max() - h / 2 - FLOOR_Y
        assert top_after < 0.8 * top_before
        # backwards: falling into the onset, rising from it, faster than it fell
        assert imp.states[onset - 1, slot, VY] < 0 < imp.states[onset, slot, VY]
        assert imp.states[onset, slot, VY] > 1.1 * abs(imp.states[onset - 1, slot, VY])


def test_occluded_bounce_is_hidden(sets):
    assert {m.condition for m in sets} == {"visible", "occluded"}
    for m in sets:
        assert m.carries_verdict
        if m.condition == "occluded":
            slot, onset = m.params["main_slots"][0], m.clips[0].onset
            assert not m.clips[1].rec.present[onset - 1:onset + 1, slot].any()
