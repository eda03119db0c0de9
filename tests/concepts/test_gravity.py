"""Gravity-v3: a ball thrown up into a raised screen comes back late; a dropped one falls through soon."""

from __future__ import annotations

import numpy as np
import pytest

from voe.concepts import get_concept
from voe.concepts.parts import FLOOR_Y
from voe.sim.scene import FEATURE_NAMES, SimConfig

Y = FEATURE_NAMES.index("y")


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Gravity-v3")
    return [c.make_set(i, s, SimConfig()) for s in (0, 7) for i in range(8)]


def _out_below(rec, slot, bottom, h, onset):
    """First frame from the onset on where the ball is seen wholly below the screen."""
    y = rec.states[onset:, slot, Y]
    with np.errstate(invalid="ignore"):
        seen = rec.present[onset:, slot] & (y + h / 2 < bottom)
    return onset + int(np.argmax(seen)) if seen.any() else None


def test_both_possible_balls_land_and_the_thrown_one_comes_out_much_later(sets):
    for m in (m for m in sets if m.condition == "occluded"):
        p, slot, onset = m.params, m.params["main_slots"][0], m.clips[0].onset
        h = p["look"]["height"]
        a, b, ab, ba = (cl.rec for cl in m.clips)
        for rec in (a, b):
            assert rec.states[-1, slot, Y] == pytest.approx(FLOOR_Y + h / 2, abs=0.1)
        t_a, t_b = (_out_below(r, slot, p["screen_bottom"], h, onset) for r in (a, b))
        assert t_a is not None and t_b is not None and t_a - t_b >= 5
        # the spliced clips keep the history of one and the exit of the other
        assert _out_below(ab, slot, p["screen_bottom"], h, onset) == t_b
        assert _out_below(ba, slot, p["screen_bottom"], h, onset) == t_a
        assert a.states[0, slot, Y] < p["screen_bottom"] < p["screen_top"] < b.states[0, slot, Y]


def test_occluded_splice_is_hidden_and_perceptual_sets_do_not_carry_the_verdict(sets):
    assert {m.condition for m in sets} == {"occluded", "perceptual"}
    for m in sets:
        slot, onset = m.params["main_slots"][0], m.clips[0].onset
        if m.condition == "occluded":
            for cl in m.clips:
                assert not cl.rec.present[onset - 2:onset + 2, slot].any()
        else:
            assert not m.carries_verdict and not m.clips[0].rec.geometry["occluders"]
