"""The bench's timestamp-jitter and dropout noise (``voe.gap.bench._clean`` / ``_record``): the
true sample times move at most the declared 4 ms and stay increasing while the stamps stay
nominal, and the declared two to four runs of 3-8 samples disappear from the recording."""

from __future__ import annotations

import numpy as np

from voe.gap.bench import _clean, _record, random_scene
from voe.gap.truths import hide


def _runs(missing: np.ndarray) -> list[tuple[int, int]]:
    """(start, length) of each maximal run of True in ``missing`` (T,)."""
    edges = np.flatnonzero(np.diff(np.r_[0, missing.astype(int), 0]))
    return [(int(a), int(b - a)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def test_jitter_moves_sample_times_at_most_4_ms_and_keeps_them_increasing():
    rng = np.random.default_rng(3)
    scene = random_scene(rng)
    hidden = hide("none", scene, rng)
    t = np.arange(201) / 100  # (T,) nominal stamps, 10 ms apart
    sigma = np.full((2, 3), 1e-3)
    pose0 = np.array([[-1.5, 0.8, 0.0], [0.5, 0.1, 0.0]])
    vel0 = np.array([[3.0, 2.0, 5.0], [0.5, 0.0, 0.0]])
    clean, t_true = _clean(np.random.default_rng(1), 0, t, pose0, vel0, hidden, sigma, "jitter")
    off = t_true - t
    assert off[0] == 0 and np.all(np.abs(off) <= 4e-3 + 1e-12) and np.all(np.diff(t_true) > 0)
    assert np.std(off[1:]) > 1e-3 and np.mean(np.abs(off[1:]) > 3e-3) > 0.02  # really jittered, about 2 ms
    ref, _ = _clean(np.random.default_rng(1), 0, t_true, pose0, vel0, hidden, sigma, "white")
    np.testing.assert_allclose(clean, ref)  # the poses are sampled at the jittered times ...
    ep = _record(np.random.default_rng(2), 0, t, clean, sigma, "jitter")
    np.testing.assert_array_equal(ep.t, t)  # ... and stamped with the nominal ones
    assert ep.pose.shape == clean.shape


def test_dropout_removes_two_to_four_runs_of_3_to_8_samples():
    t = np.arange(301) / 100
    clean = np.zeros((len(t), 2, 3))
    sigma = np.full((2, 3), 1e-3)
    n_runs, lengths = set(), set()
    for seed in range(60):
        ep = _record(np.random.default_rng(seed), 0, t, clean, sigma, "dropout")
        kept = np.isin(np.round(t, 6), np.round(ep.t, 6))  # (T,) which nominal samples were recorded
        assert kept.sum() == len(ep.t) and np.all(np.diff(ep.t) > 0)
        runs = _runs(~kept)
        assert 1 <= len(runs) <= 4 and 3 <= (~kept).sum() <= 4 * 8  # runs may overlap and merge
        assert all(a >= 20 and a + n <= len(t) - 20 + 8 and n >= 3 for a, n in runs)
        if all(n <= 8 for _, n in runs):  # no merged runs: exactly the declared number and lengths
            n_runs.add(len(runs))
            lengths |= {n for _, n in runs}
        assert np.all(np.abs(ep.pose) < 6e-3)  # the kept samples carry only the noise
    assert {2, 3, 4} <= n_runs and {3, 8} <= lengths
    white = _record(np.random.default_rng(0), 0, t, clean, sigma, "white")
    assert len(white.t) == len(t)
