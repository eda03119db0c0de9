"""Inertia-v1: the spliced clips keep a continuous position while the velocity jumps at onset."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import balanced, main_slot
from voe.concepts import get_concept
from voe.concepts.inertia import start_x
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, VX = FEATURE_NAMES.index("x"), FEATURE_NAMES.index("vx")
CFG = SimConfig()




@pytest.fixture(scope="module")
def sets():
    c = get_concept("Inertia-v1")
    return [c.make_set(i, 0, CFG) for i in range(6)]  # even: visible, odd: occluded


def test_possible_clips_are_constant_velocity(sets):
    for m in sets:
        p = m.params
        for rec, v in ((m.clips[0].rec, p["v1"]), (m.clips[1].rec, p["v2"])):
            slot = main_slot(rec)
            t = np.flatnonzero(rec.present[:, slot])
            expect = start_x(p, v, CFG.dt) + v * t * CFG.dt
            np.testing.assert_allclose(rec.states[t, slot, X], expect, atol=1e-4)
            np.testing.assert_allclose(rec.states[t, slot, VX], v, atol=1e-4)


def test_velocity_jumps_position_continuous(sets):
    for m in sets:
        p = m.params
        a, b, ab, ba = (cl.rec for cl in m.clips)
        slot, t0 = main_slot(a), p["splice_onset"]
        assert t0 == p["t_star"] + 1
        assert balanced(a, b, ab, ba)
        assert np.any(ab.frames[t0:] != a.frames[t0:])
        assert np.array_equal(ab.frames[:t0], a.frames[:t0])
        assert abs(p["v2"] - p["v1"]) > 0.7 * min(abs(p["v1"]), abs(p["v2"]))
        # true positions (visible or not): A and B meet at x* at t0 - 1
        x_a = start_x(p, p["v1"], CFG.dt) + p["v1"] * np.arange(CFG.n_frames) * CFG.dt
        x_b = start_x(p, p["v2"], CFG.dt) + p["v2"] * np.arange(CFG.n_frames) * CFG.dt
        x_ab = np.where(np.arange(CFG.n_frames) >= t0, x_b, x_a)
        assert abs(x_ab[t0] - x_ab[t0 - 1]) == pytest.approx(abs(p["v2"]) * CFG.dt)
        if m.visible:
            assert ab.states[t0, slot, X] - ab.states[t0 - 1, slot, X] == pytest.approx(p["v2"] * CFG.dt, abs=1e-4)
            assert ba.states[t0, slot, X] - ba.states[t0 - 1, slot, X] == pytest.approx(p["v1"] * CFG.dt, abs=1e-4)
            assert ab.states[t0 - 1, slot, VX] == pytest.approx(p["v1"], abs=1e-4)
            assert ab.states[t0, slot, VX] == pytest.approx(p["v2"], abs=1e-4)
        # the object is in view long enough on both sides of the onset, in both impossible clips
        for rec in (ab, ba):
            assert rec.present[:t0, slot].sum() >= 6 and rec.present[t0:, slot].sum() >= 6


def test_occluded_onset_is_hidden(sets):
    for m in sets:
        a, b = m.clips[0].rec, m.clips[1].rec
        slot, t0 = main_slot(a), m.params["splice_onset"]
        if m.visible:
            assert a.present[t0 - 1:t0 + 1, slot].all() and b.present[t0 - 1:t0 + 1, slot].all()
            continue
        p = m.params
        for rec in (a, b):
            assert not rec.present[t0 - 1:t0 + 1, slot].any()
        # at least one pixel inside the screen's edges at t0 - 1 and t0 in both clips, so no
        # anti-aliased edge of the object shows
        pix = 10.0 / CFG.size
        half_free = (p["screen_width"] - p["look"]["width"]) / 2 - pix
        for v in (p["v1"], p["v2"]):
            for t in (t0 - 1, t0):
                x = start_x(p, v, CFG.dt) + v * t * CFG.dt
                assert abs(x - p["screen_x"]) <= half_free
        assert np.array_equal(a.frames[t0], b.frames[t0])  # different positions, same pixels
