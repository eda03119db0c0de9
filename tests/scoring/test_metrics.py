"""Each metric against small examples worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from voe.scoring.metrics import accuracy, auroc, compare, relative_surprise, score_set

nan = np.nan
QUAD = np.array([False, False, True, True])  # A, B, AB, BA


def test_compare_counts_ties_as_half():
    assert compare(2.0, 1.0) == 1.0 and compare(1.0, 2.0) == 0.0 and compare(1.0, 1.0) == 0.5
    # float noise far below the tolerance is still a tie, not a win
    assert compare(0.1 + 0.2, 0.3) == 0.5
    np.testing.assert_array_equal(compare([3, 1, 1], [1, 1, 3]), [1.0, 0.5, 0.0])


def test_quadruplet_by_hand():
    traces = np.array([[1, 1, 1],    # A   S=3, peak 1
                       [1, 2, 1],    # B   S=4, peak 2
                       [1, 2, 3],    # AB  S=6, peak 3
                       [1, 1, 1.]])  # BA  S=3, peak 1
    s = score_set(traces, QUAD)
    assert (s.s_imp, s.s_pos) == (9.0, 7.0)
    assert s.accuracy == 1.0
    assert s.relative == pytest.approx(2 / 16)
    # peaks: AB 3 > A 1 (1), AB 3 > B 2 (1), BA 1 = A 1 (0.5), BA 1 < B 2 (0) -> 2.5 / 4
    assert s.accuracy_max == pytest.approx(0.625)
    assert s.n_frames == 3


def test_frames_unscored_in_one_clip_are_dropped_from_all():
    # pair: naive sums 4 (possible) vs 12 (impossible) would be a hit; on the common frames 1..2
    # it is 4 vs 2, a miss.
    traces = np.array([[nan, 2, 2], [10, 1, 1]])
    s = score_set(traces, np.array([False, True]))
    assert s.n_frames == 2 and (s.s_pos, s.s_imp) == (4.0, 2.0)
    assert s.accuracy == 0.0 and s.accuracy_max == 0.0


def test_perfect_blind_and_frame_only_scorers():
    rng = np.random.default_rng(0)
    A, B = rng.exponential(size=(2, 20))
    m = np.arange(20) >= 8
    AB, BA = np.where(m, B, A), np.where(m, A, B)  # spliced: same frames, other order
    frame_only = np.stack([A, B, AB, BA])  # a model that scores each frame alone
    assert score_set(frame_only, QUAD).accuracy == 0.5  # exact tie, not a coin flip
    assert score_set(np.ones((4, 20)), QUAD).accuracy == 0.5  # blind
    perfect = np.ones((4, 20))
    perfect[2:, 8:] += 3.0
    s = score_set(perfect, QUAD)
    assert s.accuracy == 1.0 and s.accuracy_max == 1.0
    assert accuracy(np.array([1.0, 0.5, 0.0, 1.0])) == 0.625
    assert np.isnan(accuracy(np.array([])))


def test_relative_surprise_by_hand():
    r = relative_surprise(np.array([3.0, 1.0, 0.0]), np.array([1.0, 1.0, 0.0]))
    assert r[0] == 0.5 and r[1] == 0.0 and np.isnan(r[2])


def test_auroc_by_hand():
    # impossible [3, 1], possible [1, 0]: 3>1, 3>0, 1=1 (0.5), 1>0 -> 3.5 / 4
    assert auroc(np.array([3, 1, 1, 0.0]), np.array([True, True, False, False])) == 0.875
    assert auroc(np.ones(6), np.array([1, 0, 1, 0, 1, 0], bool)) == 0.5  # all ties
    assert auroc(np.array([2, 2, 1, 1.0]), np.array([1, 1, 0, 0], bool)) == 1.0
    assert np.isnan(auroc(np.ones(2), np.array([True, True])))


def test_set_needs_both_roles():
    with pytest.raises(ValueError):
        score_set(np.ones((2, 3)), np.array([True, True]))
