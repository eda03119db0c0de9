"""Solidity-v3: the object always comes back off the wall on its own side; the splices only change when."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.timeshift import assert_time_shifted_occluded_sets
from voe.concepts import get_concept
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, VX = FEATURE_NAMES.index("x"), FEATURE_NAMES.index("vx")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Solidity-v3")
    return [c.make_set(i, s, SimConfig()) for s in (0, 7) for i in range(8)]


def test_every_object_stays_on_its_side_of_the_wall_and_bounces(sets):
    for m in sets:
        slot, wx, side = m.params["main_slots"][0], m.params["wall_x"], m.params["side"]
        for cl in m.clips:
            x = cl.rec.states[cl.rec.present[:, slot], slot, X]
            assert (side * (x - wx) > 0).all()
        for cl in m.clips[:2]:
            vx = cl.rec.states[:, slot, VX]
            assert -side * vx[0] > 0 and (side * np.nan_to_num(vx) > 0).any()  # comes back off the wall


def test_occluded_splices_return_late_or_early_at_the_same_place_and_speed(sets):
    assert_time_shifted_occluded_sets(sets)


def test_the_wall_stands_off_the_screen_centre_and_its_top_in_view(sets):
    offs = []
    for m in (m for m in sets if m.condition == "occluded"):
        occ = m.clips[0].rec.geometry["occluders"][0]
        assert m.params["wall_top"] > occ["y1"] + 0.5
        offs.append(m.params["wall_x"] - (occ["x0"] + occ["x1"]) / 2)
    assert np.ptp(offs) > 0.2  # where the wall stands in the screen varies


def test_occluded_splice_is_hidden_and_perceptual_sets_do_not_carry_the_verdict(sets):
    assert {m.condition for m in sets} == {"occluded", "perceptual"}
    for m in sets:
        slot, onset = m.params["main_slots"][0], m.clips[0].onset
        if m.condition == "occluded":
            assert m.carries_verdict
            for cl in m.clips:
                assert not cl.rec.present[onset - 2:onset + 2, slot].any()
        else:
            assert not m.carries_verdict and m.clips[0].rec.present[onset, slot]
