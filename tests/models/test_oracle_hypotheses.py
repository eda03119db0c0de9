"""The oracle's elasticity hypotheses and its return noise (seed 4418's Collision failure, issue #11)."""

from __future__ import annotations

import numpy as np

from voe.io.batch import Batch
from voe.models import statelik as sl
from voe.models.hypotheses import interval_counts, mixture_nll, refine
from voe.sim.render import visible
from voe.sim.scene import FEATURE_NAMES, Occluder

X, ANGLE = FEATURE_NAMES.index("x"), FEATURE_NAMES.index("angle")
DYN = [FEATURE_NAMES.index(f) for f in ("x", "y", "angle", "vx", "vy", "omega")]
SPACING = np.asarray([f for f in sl.RETURN_FLOOR if f > 0])


def _state(x: float, y: float = 1.0, vx: float = 0.0) -> np.ndarray:
    s = np.zeros(len(FEATURE_NAMES))
    s[[X, FEATURE_NAMES.index("y"), FEATURE_NAMES.index("vx")]] = x, y, vx
    s[[FEATURE_NAMES.index(f) for f in ("is_circle", "width", "height", "intensity")]] = 1.0, 0.5, 0.5, 0.8
    return s


def test_return_and_impact_noise_is_floored_at_half_a_cell():
    """Returns and bounces that all land exactly where predicted must not make the fit claim a point mass."""
    T, K, B = 12, 1, 6
    states = np.stack([np.stack([_state(1.0 + 0.1 * t + 0.01 * b) for t in range(T)]) for b in range(B)])[:, :, None]
    present = np.ones((B, T, K), dtype=bool)
    present[:, 4:8] = False  # hidden for 4 frames, then back where predicted
    states[~present] = np.nan
    batch = Batch(np.zeros((B, T, 4, 4), np.uint8), states.astype(np.float32), present, FEATURE_NAMES, 0.05)
    idx = sl.cont_index(FEATURE_NAMES)
    mean = np.nan_to_num(states[..., idx])  # a perfect predictor
    kind = sl.slot_kind(np.cumsum(present, axis=1) > 0, present)
    kind[:, 9:] = sl.RETURNING  # enough returns for a fit (>= 5 per clip set)
    hit = np.zeros((B, T, K), dtype=bool)
    hit[:, 1:3] = True  # bounces, predicted exactly by the best elasticity after the fact
    noise = sl.fit_noise(batch, mean, kind, np.ones((B, T, K), dtype=bool), hit)
    for sig in (noise.sigma_return, noise.sigma_contact):
        for f, q, v in zip(sl.CONT, sl.QUANTUM, sig, strict=True):
            if f in sl.CONSTANT:
                assert v < q / 2, f  # a look is carried unchanged: its fit stands
            else:
                assert v == q / 2, f
    assert noise.sigma[0] < sl.QUANTUM[0] / 2  # one frame from an observed state: no floor


def test_refined_neighbours_differ_by_at_most_the_return_floor():
    # two grid points whose return (frame 2) lies 0.13 apart in x and 0.4 in vx; frame 1 unscored
    lo, hi = _state(3.0, vx=-2.0), _state(3.13, vx=-2.4)
    pred = np.stack([np.stack([lo, lo + 5.0, lo]), np.stack([hi, hi, hi])])[:, :, None]  # (H=2, T=3, K=1, F)
    scored = np.array([[False], [False], [True]])
    counts = interval_counts(pred, scored, DYN, SPACING, ANGLE, 4, 64)
    assert counts.tolist() == [26]  # 0.13 / 0.005 in x; vx needs 0.4 / 0.025 = 16; frame 1 ignored
    pvis = np.full(pred.shape[:3], 0.99)
    out, _, _, logw = refine(pred, pvis, np.zeros(pvis.shape, bool), counts, (0.9, 0.95), ANGLE,
                              lambda s: np.full(s.shape[:-1], 0.99))
    assert out.shape[0] == 27
    gaps = np.abs(np.diff(out[:, 2, 0][:, DYN], axis=0))  # (26, 6)
    assert (gaps <= SPACING + 1e-12).all()
    np.testing.assert_allclose(np.exp(logw), np.full(27, 1 / 27))
    np.testing.assert_array_equal(out[[0, -1]], pred)  # the simulated points are kept


def test_counts_are_bounded():
    pred = np.stack([_state(0.0), _state(10.0)])[:, None, None]  # (2, 1, 1, F)
    scored = np.ones((1, 1), dtype=bool)
    assert interval_counts(pred, scored, DYN, SPACING, ANGLE, 4, 64).tolist() == [64]
    assert interval_counts(pred[[0, 0]], scored, DYN, SPACING, ANGLE, 4, 64).tolist() == [4]


def test_interpolated_hypothesis_is_visible_only_where_its_own_state_is():
    """Seed 4418: a hypothesis between a hidden and a visible grid point took the nearer one's
    visibility, and paid for a frame it should have been hidden in."""
    screen = Occluder(x0=0.0, y0=0.0, x1=3.0, y1=3.0)
    lo, hi = _state(2.0), _state(3.2)  # ball of radius 0.25: hidden at 2.0, partly out at 3.2

    def p_vis(s: np.ndarray) -> np.ndarray:
        return np.where(visible(s, [screen], (10.0, 10.0), 0.05), 0.99, 0.01)

    pred = np.stack([lo, hi])[:, None, None]  # (2, T=1, K=1, F)
    pvis = p_vis(pred)
    assert pvis[:, 0, 0].tolist() == [0.01, 0.99]
    out, vis, _, _ = refine(pred, pvis, np.zeros(pvis.shape, bool), np.array([4]), (0.9, 0.95), ANGLE, p_vis)
    np.testing.assert_allclose(out[:, 0, 0, X], [2.0, 2.3, 2.6, 2.9, 3.2])
    # 2.6 is nearer the visible point but its right edge (2.85) is still behind the screen
    assert vis[:, 0, 0].tolist() == [0.01, 0.01, 0.01, 0.99, 0.99]


def test_prior_weights_stand_for_their_span_of_elasticity():
    pred = np.stack([_state(0.0), _state(0.02), _state(0.5)])[:, None, None]  # (3, 1, 1, F)
    pvis = np.full(pred.shape[:3], 0.99)
    counts = interval_counts(pred, np.ones((1, 1), bool), DYN, SPACING, ANGLE, 1, 1000)
    assert counts.tolist() == [4, 96]
    _, _, _, logw = refine(pred, pvis, np.zeros(pvis.shape, bool), counts, (0.1, 0.15, 0.2), ANGLE,
                           lambda s: np.full(s.shape[:-1], 0.99))
    w = np.exp(logw)
    np.testing.assert_allclose(w[:4].sum(), 0.05 / (0.1 + 0.05 / 96), rtol=1e-9)  # a span of 0.05
    np.testing.assert_allclose(w.sum(), 1.0)
    # the mixture weighs hypotheses by the prior: two hypotheses, 3:1
    nll = np.array([[[np.nan, 1.0]], [[np.nan, 3.0]]])
    lp = np.log([0.75, 0.25])
    np.testing.assert_allclose(mixture_nll(nll, lp)[0, 1], -np.log(0.75 * np.exp(-1.0) + 0.25 * np.exp(-3.0)))
