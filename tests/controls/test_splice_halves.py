"""The two halves of a spliced quadruplet add up to its score, with the splice read from states.

What must hold: the frame-matching finds which possible clip each impossible frame came from, for
a suffix splice and a middle splice, also across frames the two possible clips share; the halves
sum to ``s(AB) + s(BA) - s(A) - s(B)``; a memory whose surprise only grows with the time hidden
makes the halves opposite in sign, one that knows the return time makes both positive.
"""

from __future__ import annotations

import numpy as np
import pytest

from voe.scoring.halves import ab_from_a, halves

T = 12


def _clips(cut: slice) -> tuple[dict, dict]:
    """A and B differ on every frame but 4-6 (shared); AB is A with B's frames on ``cut``."""
    a = np.arange(T, dtype=float)[:, None, None] * np.ones((T, 1, 2))
    b = a + 100.0
    b[4:7] = a[4:7]
    pa = np.ones((T, 1), dtype=bool)
    ab, ba = a.copy(), b.copy()
    ab[cut], ba[cut] = b[cut], a[cut]
    return {"A": a, "B": b, "AB": ab, "BA": ba}, {k: pa for k in ("A", "B", "AB", "BA")}


@pytest.mark.parametrize("cut", [slice(5, T), slice(8, T), slice(2, 9)])
def test_splice_is_read_from_the_states(cut):
    st, pr = _clips(cut)
    want = np.ones(T, dtype=bool)
    want[cut] = False
    got = ab_from_a(st, pr)
    shared = np.zeros(T, dtype=bool)
    shared[4:7] = True
    np.testing.assert_array_equal(got[~shared], want[~shared])  # shared frames: either side is exact


def test_halves_sum_to_the_quadruplet_score():
    st, pr = _clips(slice(8, T))
    rng = np.random.default_rng(0)
    nll = {k: rng.random(T) for k in ("A", "B", "AB", "BA")}
    d_ab, d_ba = halves(nll, ab_from_a(st, pr))
    assert d_ab + d_ba == pytest.approx(sum(nll["AB"] + nll["BA"] - nll["A"] - nll["B"]))


def test_a_growing_memory_gives_opposite_halves_and_a_law_gives_both():
    """Object hidden from frame 2; A and B return at 8 and 10, AB at 10 (late), BA at 8 (early).
    A duration memory's surprise at a return grows with the time hidden; a model that knows the
    return time pays only for returns that are off it."""
    st, pr = _clips(slice(8, T))
    from_a = ab_from_a(st, pr)
    back = {"A": 8, "B": 10, "AB": 10, "BA": 8}
    hidden_from = {"A": 2, "B": 4, "AB": 2, "BA": 4}  # BA enters as B, AB as A
    memory = {k: np.eye(T)[back[k]] * np.sqrt(back[k] - hidden_from[k]) for k in back}
    d_ab, d_ba = halves(memory, from_a)
    assert d_ab > 0 > d_ba
    law = {k: np.eye(T)[back[k]] * (5.0 if back[k] - hidden_from[k] != 6 else 0.0) for k in back}
    d_ab, d_ba = halves(law, from_a)
    assert d_ab > 0 and d_ba > 0
