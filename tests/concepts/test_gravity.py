"""Gravity-v4: a ball thrown up into a raised screen comes back down; the splices only change when."""

from __future__ import annotations

import pytest

from tests.concepts.timeshift import assert_same_exit_other_time
from voe.concepts import get_concept
from voe.concepts.parts import FLOOR_Y
from voe.sim.scene import FEATURE_NAMES, SimConfig

Y, VY = FEATURE_NAMES.index("y"), FEATURE_NAMES.index("vy")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Gravity-v4")
    return [c.make_set(i, s, SimConfig()) for s in (0, 7) for i in range(8)]


def test_both_possible_balls_rise_into_the_screen_come_back_down_and_land(sets):
    for m in (m for m in sets if m.condition == "occluded"):
        p, slot = m.params, m.params["main_slots"][0]
        h = p["look"]["height"]
        for cl in m.clips[:2]:
            st = cl.rec.states[:, slot]
            assert st[0, VY] > 0 and st[0, Y] - h / 2 < p["screen_bottom"]  # seen rising into it first
            assert st[-1, Y] == pytest.approx(FLOOR_Y + h / 2, abs=0.1)
            assert cl.rec.present[:3, slot].all()


def test_occluded_splices_come_down_late_or_early_at_the_same_place_and_speed(sets):
    for m in (m for m in sets if m.condition == "occluded"):
        assert_same_exit_other_time(m, m.params["main_slots"])


def test_occluded_splice_is_hidden_and_perceptual_sets_do_not_carry_the_verdict(sets):
    assert {m.condition for m in sets} == {"occluded", "perceptual"}
    for m in sets:
        slot, onset = m.params["main_slots"][0], m.clips[0].onset
        if m.condition == "occluded":
            for cl in m.clips:
                assert not cl.rec.present[onset - 2:onset + 2, slot].any()
        else:
            assert not m.carries_verdict and not m.clips[0].rec.geometry["occluders"]
            a, ab = (m.clips[i].rec.states[onset, slot, VY] for i in (0, 2))
            assert a < 0 < ab  # falling in A, rising in AB from the onset: it turns round in view
