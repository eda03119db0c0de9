"""Timing jitter (voe.gap.jitter): estimated from jittered recordings only, reproduced in the
clean replicates, and no change at all to recordings without it."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from voe.gap.bench import make_case
from voe.gap.departure import ALPHA
from voe.gap.finder import GapFinder
from voe.gap.jitter import jitter_noise, timing_jitter
from voe.gap.recordings import load_recordings
from voe.gap.scene import load_scene
from voe.gap.shooting import noise_model
from voe.gap.stages import GapConfig, locate_step, prepare
from voe.gap.synth import pose_noise, replicate_noise

REAL = Path(__file__).resolve().parents[2] / "data" / "real" / "single-pendulum"


def _jitter(seed: int, truth: str, noise_kind: str):
    eps = make_case(np.random.default_rng(seed), truth, noise_kind=noise_kind).episodes
    return timing_jitter(eps, noise_model(eps)[1])


def test_jitter_is_found_where_samples_are_off_their_stamps_and_only_there():
    """The bench's jitter is Gaussian of 2 ms clipped at 4 ms (standard deviation 1.76 ms);
    development cases of white, coloured and dropout noise and a floor patch show none."""
    for seed in (6685240, 1078241):
        j = _jitter(seed, "none", "jitter")
        assert j is not None and 1.4e-3 < j.seconds < 2.4e-3
        assert np.all(j.sensor[:, :2] < 1.5e-3)  # the bench's 1 mm sensor noise, not the jitter's
    for seed, truth, kind in ((6685242, "none", "white"), (1078202, "none", "coloured"),
                              (1967241, "none", "dropout"), (6685140, "floor_patch", "white")):
        assert _jitter(seed, truth, kind) is None, (seed, kind)


def test_the_real_pendulum_shows_no_jitter():
    spec, _, _ = load_scene(REAL / "scene.json")
    eps = load_recordings(REAL / "recordings.csv", spec)
    assert timing_jitter(eps, noise_model(eps)[1]) is None


def test_without_jitter_the_replicate_noise_is_exactly_pose_noise():
    """Recordings without jitter must get the very draws they got before jitter was modelled, so
    that earlier results stand."""
    clean = np.random.default_rng(0).normal(size=(50, 2, 3))
    sigma, phi = np.full((2, 3), 1e-3), np.zeros((2, 3))
    t = np.arange(50) / 100
    a = replicate_noise(clean, t, sigma, phi, None, np.random.default_rng(1))
    assert np.array_equal(a, pose_noise(clean.shape, sigma, phi, np.random.default_rng(1)))


def test_jitter_noise_is_velocity_times_the_time_error():
    t = np.arange(2001) / 100
    clean = np.zeros((len(t), 1, 3))
    clean[:, 0, 0] = 3.0 * t  # 3 m/s along x, at rest otherwise
    e = jitter_noise(clean, t, 2e-3, np.random.default_rng(0))
    assert np.all(e[:, 0, 1:] == 0)
    assert abs(np.std(e[:, 0, 0]) / 6e-3 - 1) < 0.05


def test_clean_jittered_cases_are_not_called_unexplained():
    """Development cases 6685247 and 1078255 (clean, jittered): against replicates with the noise
    model alone (ffc6ae3, the finder's own draws) they were located (5 and 3 stretches) with departure
    p 0.0001 and 0.001, so ``unexplained`` for clean recordings; with the jitter reproduced, p was 0.21
    and 0.26, and since session 61 (restarts from the half-step start velocity) 0.026 and 0.26: above
    the departure test's ``ALPHA``, so not ``unexplained``. A draw: of 40 other clean jittered cases
    of the same seeds (6685300-319, 1078300-319; docs/bench-runs/dev-s61/jitter_p_*.txt) none fell
    below ``ALPHA`` and one below 0.05, with the half step or without it."""
    for seed in (6685247, 1078255):
        case = make_case(np.random.default_rng(seed), "none", noise_kind="jitter")
        p = prepare(case.scene, case.episodes, GapFinder(seed=seed).effects, GapConfig())
        assert p.jitter is not None
        assert locate_step(p, GapConfig(), np.random.default_rng(seed)).departure_p > ALPHA, seed
