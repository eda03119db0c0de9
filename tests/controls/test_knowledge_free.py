"""Knowledge-free controls: hand-worked values, and exact ties wherever the balance promises them."""

from __future__ import annotations

import numpy as np
import pytest

from voe.controls.probe_runs import (
    FRAMECOPY_THRESHOLD,
    PROBE_STATISTICS,
    STRESS,
    as_run,
    set_balance,
    statistic,
)
from voe.controls.smoothness import ACC_SCALE, Smoothness
from voe.controls.statistics import Height, MotionEnergy, Speed
from voe.controls.stress import fit_logistic, folds
from voe.io.probeset import load_probe_set
from voe.scoring.table import set_table

NAMES = ("x", "y", "angle", "vx", "vy", "omega", "is_circle", "is_box", "width", "height", "intensity")


def _arrays(frames=None, xy=None, v=None, present=None):
    B, T = (frames.shape[:2] if frames is not None else xy.shape[:2])
    K = 1 if xy is None else xy.shape[2]
    st = np.zeros((B, T, K, len(NAMES)), np.float32)
    if xy is not None:
        st[..., :2] = xy
    if v is not None:
        st[..., 3:5] = v
    pres = np.ones((B, T, K), bool) if present is None else present
    return {"frames": frames if frames is not None else np.zeros((B, T, 2, 2), np.uint8),
            "states": st, "present": pres}


def test_motion_energy_height_and_speed_by_hand():
    f = np.zeros((1, 3, 2, 2), np.uint8)
    f[0, 1, 0, 0], f[0, 2, 1, 1] = 10, 3
    assert MotionEnergy().traces(_arrays(frames=f), NAMES).tolist() == [[0, 10, 13]]
    xy = np.array([[[[1, 2], [3, 4]], [[1, 6], [0, 0]]]], np.float32)  # (1, 2, 2, 2)
    present = np.array([[[True, True], [True, False]]])
    assert Height().traces(_arrays(xy=xy, present=present), NAMES).tolist() == [[3.0, 6.0]]
    v = np.array([[[[3, 4]], [[0, 0]]]], np.float32)
    assert Speed().traces(_arrays(xy=np.zeros((1, 2, 1, 2)), v=v), NAMES).tolist() == [[5.0, 0.0]]


def test_smoothness_is_zero_on_a_straight_track_and_jolts_at_a_turn_and_across_a_teleport():
    t = np.arange(6, dtype=np.float32)
    straight = np.stack([t * 0.1, np.zeros(6)], -1)[None, :, None]  # (1, 6, 1, 2)
    assert np.allclose(Smoothness().traces(_arrays(xy=straight), NAMES), 0, atol=1e-5)
    bounce = straight.copy()
    bounce[0, 3:, 0, 0] = 0.3 - (t[3:] - 3) * 0.1  # reverses at frame 4
    tr = Smoothness().traces(_arrays(xy=bounce), NAMES)[0]
    assert tr[4] == pytest.approx(0.2 / ACC_SCALE + np.pi, rel=1e-5) and np.allclose(tr[[1, 2, 3, 5]], 0, atol=1e-5)
    hidden = np.ones((1, 6, 1), bool)
    hidden[0, 2:4] = False
    assert np.allclose(Smoothness().traces(_arrays(xy=straight, present=hidden), NAMES), 0, atol=1e-5)  # smooth behind a screen
    jump = straight.copy()
    jump[0, 4:, 0, 0] += 1.0
    assert Smoothness().traces(_arrays(xy=jump, present=hidden), NAMES)[0, 4] == pytest.approx(1.0 / 3 / ACC_SCALE, rel=1e-5)


def test_logistic_regression_separates_and_folds_keep_sets_whole():
    rng = np.random.default_rng(0)
    X = np.concatenate([rng.normal(-1, 0.3, (50, 2)), rng.normal(1, 0.3, (50, 2))])
    y = np.r_[np.zeros(50), np.ones(50)]
    w, b, mu, sd = fit_logistic(X, y, 1 - y)
    assert (((X - mu) / sd @ w + b > 0) == y.astype(bool)).mean() > 0.95
    # counts are occurrences: one row seen twice fits like two identical rows
    w2, b2, _, _ = fit_logistic(np.r_[X, X[:1]], np.r_[y, y[:1]], np.r_[1 - y, 1 - y[:1]])
    w3, b3, _, _ = fit_logistic(X, y + np.eye(100)[0] * y[0], (1 - y) + np.eye(100)[0] * (1 - y[0]))
    assert np.allclose(w2, w3, atol=1e-5) and b2 == pytest.approx(b3, abs=1e-5)
    f = folds(np.array(["s2", "s1", "s1", "s3", "s2", "s9"]), k=2)
    assert f.tolist() == [1, 0, 0, 0, 1, 1]


@pytest.fixture(scope="module")
def runs(tiny_probes):
    ps = load_probe_set(tiny_probes)
    names = [f"stat:{n}" for n in (*PROBE_STATISTICS, *STRESS)]
    return ps, set_balance(ps), {n: set_table(as_run(ps, statistic(ps, n).traces, n, n)) for n in names}


@pytest.mark.parametrize(("name", "balance"), [("stat:density", "F"), ("stat:stress-frame", "F"),
                                               ("stat:motion-energy", "M"), ("stat:stress-step", "M"),
                                               ("stat:height", "S"), ("stat:speed", "S")])
def test_scorers_tie_exactly_on_every_set_that_reaches_their_balance(name, balance, runs):
    _, bal, tables = runs
    sets = tables[name].merge(bal, on=["concept", "set_id"])
    assert sets[balance].any(), f"no {balance}-balanced set in the tiny probe set"
    tied = sets[sets[balance]]
    assert (tied["accuracy"] == 0.5).all(), tied[["set_id", "s_imp", "s_pos"]]
    assert np.allclose(tied["s_imp"], tied["s_pos"], rtol=1e-12, atol=1e-9)


def test_stress_frame_scores_identical_frames_identically(runs, tiny_probes):
    ps, bal, _ = runs
    tr = statistic(ps, "stat:stress-frame").traces
    sid = bal.loc[bal["F"], "set_id"].iloc[0]
    rows = np.flatnonzero(ps.index["set_id"].to_numpy() == sid)
    imp = ps.index["role"].to_numpy()[rows] == "impossible"
    # identical frame multisets -> identical multisets of scores, bit for bit
    assert sorted(tr[rows[imp]].ravel().tolist()) == sorted(tr[rows[~imp]].ravel().tolist())


def test_flip_count_threshold_is_frame_copys():
    from voe.models.framecopy import THRESHOLD

    assert FRAMECOPY_THRESHOLD == THRESHOLD
