"""Helpers shared by the concept tests."""

import numpy as np

from voe.io.balance import quadruplet_problem


def main_slot(rec) -> int:
    """The main object's slot: the one on the floor (distractors ride the top lane)."""
    low = np.where(rec.present, rec.states[:, :, 1], np.inf).min(axis=0) < 5  # (K,)
    return int(np.flatnonzero(low)[0])


def balanced(a, b, ab, ba) -> bool:
    """The impossible pair holds exactly the frames of the possible pair."""
    return quadruplet_problem([a.frames, b.frames], [ab.frames, ba.frames]) is None


def assert_pair(m, lo: int, hi: int) -> None:
    """A pair-fallback set: onset in [lo, hi), identical frames and states before it, different after."""
    from voe.io.balance import pair_problem

    pos, imp = (cl.rec for cl in m.clips)
    onset = m.clips[0].onset
    assert lo <= onset < hi
    assert pair_problem(pos.frames, imp.frames, onset) is None
    assert np.array_equal(pos.states[:onset], imp.states[:onset], equal_nan=True)
