"""A spliced quadruplet counts as learned only if each impossible clip surprises on its own.

What must hold: a fading memory (surprise at a return that only falls with the time hidden)
gets a sum that can be right on every set but halves at exactly 0.5, and the verdict is then
*not learned* (one-sided); a model surprised by both violations keeps *learned*; frames not
scored in every clip are dropped from the halves as from the sum; a verdict that is not
*learned* never changes.
"""

from __future__ import annotations

import numpy as np

from voe.scoring.halves import half_score, quadruplet_halves
from voe.scoring.verdict import INCONCLUSIVE, LEARNED, NOT_LEARNED, verdict, with_halves

T = 10
FROM_A = np.array([True] * 5 + [False] * 5)  # AB shows A then B; BA shows B then A


def _nll(d_ab: float, d_ba: float) -> dict[str, np.ndarray]:
    base = np.ones(T)
    ab, ba = base.copy(), base.copy()
    ab[7] += d_ab  # the return frame after the splice
    ba[7] += d_ba
    return {"A": base.copy(), "B": base.copy(), "AB": ab, "BA": ba}


def test_a_fading_memory_has_halves_at_one_half_even_when_its_sum_is_right():
    sets = [quadruplet_halves(_nll(+3.0, -1.0), FROM_A, 0.01, 1e-9) for _ in range(10)]  # sum +2 every set
    assert sets == [0.5] * 10
    sum_v = verdict(1.0, 1.0, 1.0, 0.002)
    half_v = verdict(0.5, 0.5, 0.5, 1.0)
    assert sum_v[0] == LEARNED and with_halves(sum_v, half_v) == (NOT_LEARNED, "one-sided")


def test_both_halves_right_keeps_learned_and_ties_count_half():
    assert quadruplet_halves(_nll(2.0, 1.0), FROM_A, 0.01, 1e-9) == 1.0
    assert quadruplet_halves(_nll(2.0, 0.0), FROM_A, 0.01, 1e-9) == 0.75
    assert half_score(0.005, 0.0, 0.01, 0.0) == 0.5
    sum_v = verdict(1.0, 1.0, 1.0, 0.002)
    assert with_halves(sum_v, verdict(1.0, 1.0, 1.0, 0.002)) == sum_v
    assert with_halves(sum_v, None) == sum_v  # a pair concept has no halves


def test_only_a_learned_verdict_can_change():
    for v in ((NOT_LEARNED, "reversed"), (INCONCLUSIVE, "chance")):
        assert with_halves(v, (NOT_LEARNED, "")) == v
    assert with_halves((LEARNED, ""), (INCONCLUSIVE, "halves unchecked (probe set not found)"))[1].startswith("halves")


def test_unscored_frames_are_dropped_from_the_halves():
    nll = _nll(2.0, 1.0)
    nll["A"][0] = np.nan  # frame 0 not scored in A: dropped from every clip
    assert quadruplet_halves(nll, FROM_A, 0.01, 1e-9) == 1.0
    nll["BA"][7] = np.nan  # the return frame not scored in BA: dropped from AB too, both halves tie
    assert quadruplet_halves(nll, FROM_A, 0.01, 1e-9) == 0.5
