"""Checks shared by the time-shifted hidden splices (Solidity-v3, Gravity-v4, Collision-v4)."""

import numpy as np


def runs(rec, slot):
    """``(first, last)`` frame of the first run of frames where ``slot`` exists but is hidden."""
    hid = np.flatnonzero(rec.exists[:, slot] & ~rec.present[:, slot])
    if hid.size == 0:
        return None
    end = int(np.argmax(np.diff(np.append(hid, -9)) != 1))
    return int(hid[0]), int(hid[end])


def assert_same_exit_other_time(m, slots):
    """Every clip brings each hidden object back where it went in, at the same speed (to one
    velocity cell); B does so ``shift`` frames after A, AB ``shift`` frames late, BA as early."""
    a, b, ab, ba = (cl.rec for cl in m.clips)
    shift = m.params["shift"]
    for s in slots:
        (a0, a1), (b0, b1), (ab0, ab1), (ba0, ba1) = (runs(r, s) for r in (a, b, ab, ba))
        assert (b0 - a0, b1 - a1) == (shift, shift)
        assert (ab0, ab1) == (a0, b1) and (ba0, ba1) == (b0, a1)  # late by shift, early by shift
        for r, (i, o) in zip((a, b, ab, ba), ((a0, a1), (b0, b1), (ab0, ab1), (ba0, ba1)), strict=True):
            seen_in, seen_out = r.states[i - 1, s], r.states[o + 1, s]  # last before, first after
            assert np.isfinite(seen_in).all() and np.isfinite(seen_out).all()
            assert abs(seen_out[0] - seen_in[0]) < 0.5 and abs(seen_out[1] - seen_in[1]) < 0.5
        outs = [r.states[o + 1, s, 3:5] for r, o in ((a, a1), (b, b1), (ab, b1), (ba, a1))]
        assert np.allclose(outs, outs[0], atol=0.06)  # the same exit velocity in all four


def assert_pass_through_shows_after_late_return(m, slots, dt=0.05):
    """An observer without walls or collisions (constant velocity from the last frame seen) would
    see each object past the screen's far edge only after even the late splice (AB) brings it
    back: otherwise it pays for "not out yet" frames in AB alone and passes without the concept."""
    ab = m.clips[2].rec
    occ = ab.geometry["occluders"][0]
    for s in slots:
        first, last = runs(ab, s)
        x, vx, w = (float(ab.states[first - 1, s, i]) for i in (0, 3, 8))
        gap = occ["x1"] - (x + w / 2) if vx > 0 else (x - w / 2) - occ["x0"]
        assert first - 1 + gap / abs(vx) / dt > last + 1


def assert_time_shifted_occluded_sets(sets):
    """Every occluded set is a time-shifted splice whose pass-through shows only after the late return."""
    occl = [m for m in sets if m.condition == "occluded"]
    assert occl
    for m in occl:
        assert_same_exit_other_time(m, m.params["main_slots"])
        assert_pass_through_shows_after_late_return(m, m.params["main_slots"])
