"""Energy-v2: after its one bounce the possible ball peaks below the top of its toss, the
impossible one rises above it."""

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
    c = get_concept("Energy-v2")
    return [c.make_set(i, s, SimConfig()) for s in (0, 1) for i in range(12)]


def _height(rec, slot, r, frames):
    """Highest bottom height above the floor on the given frames where the ball is seen."""
    return float(np.nanmax(rec.states[frames, slot, Y])) - r - FLOOR_Y


def _bounces(rec, slot) -> int:
    """Falling-to-rising turns of a ball seen on every frame."""
    v = rec.states[:, slot, VY]  # (T,)
    assert not np.isnan(v).any()
    return int(((v[1:] > 0) & (v[:-1] < 0)).sum())


def test_pair_shares_the_prefix_and_differs_after(sets):
    for m in sets:
        assert_pair(m, 20, 30)


def test_tossed_up_to_its_drop_height_and_onset_is_the_first_impact(sets):
    for m in sets:
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        pos = m.clips[0].rec
        r = p["look"]["height"] / 2
        assert pos.states[0, slot, VY] > 4.0  # thrown upwards
        assert _height(pos, slot, r, slice(0, onset)) == pytest.approx(p["drop"], abs=0.05)
        vy = pos.states[:onset, slot, VY]
        seen = vy[~np.isnan(vy)]
        assert (np.diff(seen) < 0).all()  # up and down under gravity alone until the impact


def test_one_bounce_in_either_clip(sets):
    for m in (m for m in sets if m.visible):
        slot = m.params["main_slots"][0]
        assert [_bounces(cl.rec, slot) for cl in m.clips] == [1, 1]


def test_possible_peaks_lower_and_impossible_higher_than_the_toss(sets):
    for m in sets:
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        r, h = p["look"]["height"] / 2, p["drop"]
        pos, imp = (cl.rec for cl in m.clips)
        assert _height(pos, slot, r, slice(onset, None)) < 0.75 * h
        assert _height(imp, slot, r, slice(onset, None)) > 1.2 * h


def test_same_frames_in_view_and_impact_hidden_in_occluded_sets(sets):
    for m in sets:
        slot = m.params["main_slots"][0]
        pos, imp = (cl.rec for cl in m.clips)
        np.testing.assert_array_equal(pos.present[:, slot], imp.present[:, slot])
        assert imp.present[m.clips[0].onset, slot] == m.visible
