"""The built-in likelihoods are normalised over the observation spaces they define."""

from __future__ import annotations

import itertools

import numpy as np

from voe.io.batch import Batch
from voe.models.framecopy import FrameCopy
from voe.models.statelik import QUANTUM, cell_logp, gaussian_nll


def test_quantised_gaussian_sums_to_one_over_cells():
    sigma = np.array([0.03, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3])
    cells = np.arange(-1000, 1001) * QUANTUM[0] + 0.004  # the uniform component's whole RANGE (x in -5..15)
    r = np.zeros((cells.size, 9))
    r[:, 0] = cells
    obs = r + 5.0
    total = np.exp(cell_logp(r, sigma, obs)[:, 0]).sum()
    assert abs(total - 1.0) < 1e-6
    assert (gaussian_nll(r, sigma, obs) >= 0).all()  # probabilities of cells: surprise never negative


def test_quantised_gaussian_far_tail_is_finite_and_capped():
    r = np.zeros((3, 9))
    r[:, 3] = [0.0, 0.02, 10.0]
    nll = gaussian_nll(r, np.full(9, 0.01), r + 1.0)
    assert np.isfinite(nll).all() and nll[0] < nll[1] <= nll[2] + 1e-9
    # the uniform component caps a wrong feature at log(1 / 0.01) + log(40 / 0.05) = 11.3 nats
    assert nll[2] - nll[0] < 11.4


def test_frame_copy_sums_to_one_over_binary_frames():
    prev = np.array([[0, 255], [255, 0]], dtype=np.uint8)
    frames = []
    for bits in itertools.product([0, 255], repeat=4):
        frames.append(np.stack([prev, np.array(bits, dtype=np.uint8).reshape(2, 2)]))
    frames = np.stack(frames)  # (16, 2, 2, 2)
    B = len(frames)
    batch = Batch(frames, np.zeros((B, 2, 1, 11), np.float32), np.zeros((B, 2, 1), bool), ("x",), 0.05)
    nll = FrameCopy(eps=0.1).frame_nll(batch)
    assert np.isnan(nll[:, 0]).all()
    assert abs(np.exp(-nll[:, 1]).sum() - 1.0) < 1e-12


def test_untrained_state_networks_are_uniform(tiny_batch):
    """Untrained, every frame costs the same whatever it shows: ties, i.e. chance, on any set."""
    from voe.models.loading import load_model

    for name in ("interaction-v2", "interaction-v3", "mlp"):
        m = load_model(name)
        nll = m.frame_nll(tiny_batch)[:, m.warmup:]
        assert np.ptp(nll) < 1e-5, name


def test_noise_fit_is_maximum_likelihood_under_the_outlier_mixture():
    """A few wild residuals (mispredicted contacts) must not set sigma for every frame."""
    from voe.models.statelik import robust_sigma

    rng = np.random.default_rng(0)
    r = rng.normal(0.0, 0.02, size=(5000, 9))
    r[:25] = rng.uniform(-3, 3, size=(25, 9))  # 0.5 % outliers
    rms = np.sqrt((r ** 2).mean(0))
    sig = robust_sigma(r)
    assert (rms > 0.1).all()  # the RMS is ruined by 25 outliers
    np.testing.assert_allclose(sig, 0.02, rtol=0.05)


def test_shape_prior_scores_a_returning_look_like_a_new_one(tiny_batch):
    """``shape_prior`` makes width and height cost what a new object's would, nothing else."""
    from voe.models.statelik import NEW, Noise, cont_index, score, slot_kind

    b = tiny_batch
    kind = slot_kind(np.cumsum(b.present, axis=1) > 0, b.present)
    mean = np.nan_to_num(b.states[..., cont_index(b.feature_names)].astype(np.float64))  # perfect
    circ = b.states[..., b.feature("is_circle")] > 0.5
    noise = Noise()
    plain = score(b, mean, kind, noise, circle_mem=circ)
    every = np.ones_like(b.present)
    blind = score(b, mean, kind, noise, circle_mem=circ, shape_prior=every & (kind != NEW))
    assert np.nansum(blind) > np.nansum(plain)  # remembering the look is worth something
    none = score(b, mean, kind, noise, circle_mem=circ, shape_prior=np.zeros_like(every))
    np.testing.assert_allclose(none, plain)
