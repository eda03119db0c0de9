"""The built-in likelihoods are normalised over the observation spaces they define."""

from __future__ import annotations

import itertools

import numpy as np

from voe.io.batch import Batch
from voe.models.framecopy import FrameCopy
from voe.models.statelik import QUANTUM, cell_logp, gaussian_nll


def test_quantised_gaussian_sums_to_one_over_cells():
    sigma = np.array([0.03, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3])
    cells = np.arange(-600, 601) * QUANTUM[0] + 0.004  # every cell within +-6 wide sigmas, off-centre
    r = np.zeros((cells.size, 9))
    r[:, 0] = cells
    total = np.exp(cell_logp(r, sigma)[:, 0]).sum()
    assert abs(total - 1.0) < 1e-6
    assert (gaussian_nll(r, sigma) >= 0).all()  # probabilities of cells: surprise never negative


def test_quantised_gaussian_far_tail_is_finite_and_monotone():
    r = np.zeros((3, 9))
    r[:, 3] = [1.0, 10.0, 100.0]
    nll = gaussian_nll(r, np.full(9, 0.01))
    assert np.isfinite(nll).all() and nll[0] < nll[1] < nll[2]


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
