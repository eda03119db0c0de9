"""Energy-v6: a ball slides into a wall and comes back slower; the impossible clip is that clip
played backwards, so only its bounce gains energy. Each set also holds the left-right mirrors of
both clips, and nothing moves vertically, so every signed step and velocity is balanced."""

from __future__ import annotations

import math

import numpy as np
import pytest

from voe.concepts import get_concept
from voe.concepts.energy import _miss_gap, sliding
from voe.io.balance import ClipData, measure
from voe.sim.rollout import Recording
from voe.sim.scene import FEATURE_NAMES, SimConfig

X, Y, VX, VY, ANGLE, OMEGA = (FEATURE_NAMES.index(n) for n in ("x", "y", "vx", "vy", "angle", "omega"))
DT = SimConfig().dt


@pytest.fixture(scope="module")
def sets():
    c = get_concept("Energy-v6")
    return [c.make_set(i, s, SimConfig()) for s in (0, 7) for i in range(8)]


def _data(m, role):
    return [ClipData(c.rec.frames, c.rec.states, c.rec.present) for c in m.clips if c.role == role]


def test_impossible_is_the_possible_clip_reversed(sets):
    for m in sets:
        pos, imp = (cl.rec for cl in m.clips[:2])
        np.testing.assert_array_equal(imp.frames, pos.frames[::-1])
        np.testing.assert_array_equal(imp.states[..., X], pos.states[::-1, :, X])
        np.testing.assert_array_equal(imp.states[..., VX], -pos.states[::-1, :, VX] + 0.0)


def test_one_wall_bounce_that_loses_energy_forwards_and_gains_it_backwards(sets):
    for m in sets:
        slot, onset, T = m.params["main_slots"][0], m.clips[0].onset, SimConfig().n_frames
        pos, imp = (cl.rec for cl in m.clips[:2])
        vx = pos.states[:, slot, VX]
        if m.condition == "visible":
            assert (np.diff(np.sign(vx)) != 0).sum() == 1  # one bounce
            speeds = np.unique(np.abs(vx))
            assert speeds.size == 2 and speeds[0] == pytest.approx(m.params["restitution"] * speeds[1], rel=0.02)
            # backwards: slow into the onset, fast out of it
            v_in, v_out = imp.states[onset - 1, slot, VX], imp.states[onset, slot, VX]
            assert np.sign(v_in) == -np.sign(v_out) and abs(v_out) > 1.3 * abs(v_in)
        assert T - onset > 8 and onset > 8


def test_nothing_moves_vertically_or_turns(sets):
    """The ball slides (frictionless floor and wall), the distractors slide on their lane: every
    object keeps its height on every frame, with no vertical velocity, angle or spin stored."""
    for m in sets:
        for c in m.clips:
            st = c.rec.states
            for k in range(st.shape[1]):
                y = st[:, k, Y][~np.isnan(st[:, k, Y])]
                assert y.size == 0 or np.ptp(y) == 0
            for f in (VY, ANGLE, OMEGA):
                assert np.nanmax(np.abs(st[..., f]), initial=0.0) == 0.0


def test_sliding_refuses_an_object_that_turned_or_left_its_support():
    st = np.zeros((3, 1, len(FEATURE_NAMES)), np.float32)
    st[1, 0, VY] = 0.03  # solver jitter: stored as 0
    rec = sliding(Recording(np.zeros((3, 8, 8), np.uint8), st.copy(), np.ones((3, 1), bool),
                            np.ones((3, 1), bool), {}))
    assert rec.states[..., VY].max() == 0.0
    st[1, 0, VY] = 2.0  # a real vertical motion
    with pytest.raises(ValueError, match="vy"):
        sliding(Recording(np.zeros((3, 8, 8), np.uint8), st, np.ones((3, 1), bool), np.ones((3, 1), bool), {}))


def test_occluded_bounce_is_hidden(sets):
    assert {m.condition for m in sets} == {"visible", "occluded"}
    for m in sets:
        assert m.carries_verdict
        slot, onset = m.params["main_slots"][0], m.clips[0].onset
        hidden = ~m.clips[1].rec.present[onset - 2:onset + 2, slot]
        assert hidden.all() if m.condition == "occluded" else not hidden.any()
        # the wall is taller than the screen: its top shows in both conditions
        occ = m.clips[0].rec.geometry.get("occluders", [])
        walls = [s for s in m.clips[0].rec.geometry["statics"] if s["kind"] == "wall" and s["a"][1] < 2]
        assert len(walls) == 1 and all(max(walls[0]["a"][1], walls[0]["b"][1]) > o["y1"] + 1 for o in occ)


def test_impact_falls_mid_interval_so_constant_velocity_misses_it_equally_both_ways(sets):
    """Energy-v3's impacts fell early or late in their frame (constant velocity 0.95 on seed 2026)."""
    for m in (m for m in sets if m.condition == "visible"):
        slot = m.params["main_slots"][0]
        for cl in m.clips:
            x, vx = (cl.rec.states[:, slot, i].astype(np.float64) for i in (X, VX))
            f = int(np.flatnonzero(np.diff(np.sign(vx)) != 0)[0])
            miss_in = abs(x[f + 1] - (x[f] + vx[f] * DT))
            miss_back = abs(x[f] - (x[f + 1] - vx[f + 1] * DT))
            assert miss_in > 0.05 and abs(miss_in - miss_back) < 0.05 * (miss_in + miss_back)
        assert abs(_miss_gap(m.clips[0].rec.states, slot, DT)) < 0.05


def test_each_set_holds_both_clips_and_their_exact_mirrors(sets):
    for m in sets:
        assert m.kind == "mirrored"
        assert [(c.variant, c.role) for c in m.clips] == [
            ("possible", "possible"), ("impossible", "impossible"),
            ("mirror-possible", "possible"), ("mirror-impossible", "impossible")]
        for c, mc in ((m.clips[0], m.clips[2]), (m.clips[1], m.clips[3])):
            assert np.abs(mc.rec.frames.astype(int) - c.rec.frames[..., ::-1]).max() <= 3
            np.testing.assert_array_equal(mc.rec.states[..., X], np.float32(10.0) - c.rec.states[..., X])
            np.testing.assert_array_equal(mc.rec.states[..., VX], -c.rec.states[..., VX])
            np.testing.assert_array_equal(mc.rec.states[..., Y], c.rec.states[..., Y])


def test_every_signed_step_is_balanced_including_vertical(sets):
    """v5 could not reach ``Y`` (a reversed vertical bounce rises slower than it fell); v6 does, and
    a scorer of the signed vertical or horizontal motion ties exactly. Without the mirrors ``X``
    is lost, so the check can fail."""
    for m in sets:
        pos, imp = _data(m, "possible"), _data(m, "impossible")
        full, half = measure(pos, imp, FEATURE_NAMES), measure(pos[:1], imp[:1], FEATURE_NAMES)
        assert str(full) == "F+M+P+V+H+D+X+Y" and half.Y and not half.X
        slot = m.params["main_slots"][0]
        for f in (VX, VY):
            score = [math.fsum(np.nan_to_num(c.rec.states[1:, slot, f]).tolist()) for c in m.clips]
            assert score[1] + score[3] == score[0] + score[2]
