"""Property tests of the metrics: invariance to the order of sets and clips, ties, all-NaN."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from voe.scoring.metrics import TIE_ATOL, accuracy, auroc, compare, score_set

from .mutate import FUZZ

surprise = st.floats(-50, 50, allow_nan=False, width=32)
traces4 = arrays(np.float64, (4, 6), elements=surprise)
IMP4 = np.array([False, False, True, True])


@FUZZ
@given(traces=traces4, perm=st.permutations(range(4)))
def test_set_score_ignores_clip_order(traces, perm):
    a = score_set(traces, IMP4)
    b = score_set(traces[list(perm)], IMP4[list(perm)])
    assert a.accuracy == b.accuracy and a.accuracy_max == b.accuracy_max
    assert a.n_frames == b.n_frames


@FUZZ
@given(traces=traces4)
def test_swapping_labels_mirrors_the_score(traces):
    a, b = score_set(traces, IMP4), score_set(traces, ~IMP4)
    assert a.accuracy + b.accuracy == 1.0 and abs(a.accuracy_max + b.accuracy_max - 1.0) < 1e-12


@FUZZ
@given(traces=traces4)
def test_frame_only_scorer_ties_on_a_splice(traces):
    """Impossible clips holding exactly the possible clips' frames (any order) tie exactly."""
    frames = np.concatenate([traces[0], traces[1]])              # the 12 frames of A and B
    spliced = np.stack([traces[0], traces[1], frames[::-1][:6], frames[::-1][6:]])
    assert score_set(spliced, IMP4).accuracy == 0.5


@FUZZ
@given(traces=traces4, cols=st.lists(st.integers(0, 5), min_size=1, max_size=6))
def test_nan_frames_are_dropped_from_every_clip(traces, cols):
    t = traces.copy()
    t[0, cols] = np.nan                                           # one clip unscored on some frames
    keep = [c for c in range(6) if c not in cols]
    assert score_set(t, IMP4).accuracy == score_set(traces[:, keep], IMP4).accuracy
    all_nan = np.full((4, 6), np.nan)
    s = score_set(all_nan, IMP4)
    assert s.accuracy == 0.5 and s.accuracy_max == 0.5 and s.n_frames == 0 and np.isnan(s.relative)


@FUZZ
@given(scores=st.lists(st.sampled_from([0.0, 1.0, 1.0, 2.0, 3.0]), min_size=4, max_size=30),
       data=st.data())
def test_accuracy_and_auroc_ignore_set_order_and_count_ties_half(scores, data):
    s = np.array(scores)
    y = np.array(data.draw(st.lists(st.booleans(), min_size=len(s), max_size=len(s))))
    perm = np.array(data.draw(st.permutations(range(len(s)))))
    a = auroc(s, y)
    if y.all() or not y.any():
        assert np.isnan(a)
        return
    assert a == auroc(s[perm], y[perm])
    assert 0.0 <= a <= 1.0 and auroc(np.zeros_like(s), y) == 0.5     # all tied: chance
    sets = compare(s, s[::-1], TIE_ATOL)
    assert set(np.unique(sets)) <= {0.0, 0.5, 1.0}
    assert accuracy(sets) == accuracy(sets[perm]) and np.isnan(accuracy(np.array([])))
