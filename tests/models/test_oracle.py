"""The physics oracle: an exact Bayesian mixture over elasticity, and what it sees."""

from __future__ import annotations

import numpy as np
import pytest

from voe.concepts import get_concept
from voe.io.batch import Batch
from voe.models import statelik as sl
from voe.models.oracle import ELASTICITY_GRID, PhysicsOracle, mixture_nll
from voe.sim.scene import FEATURE_NAMES, SimConfig


def test_mixture_is_the_bayesian_predictive():
    # two hypotheses, hand-worked: p(o_t | o_<t) = sum_h p(h | o_<t) p(o_t | h)
    nll = np.array([[[np.nan, 1.0, 2.0]], [[np.nan, 3.0, 0.5]]])  # (H=2, B=1, T=3)
    p = np.exp(-nll[:, 0, 1:])  # (2, 2) per-frame likelihoods
    f1 = -np.log(0.5 * p[0, 0] + 0.5 * p[1, 0])
    w = np.array([p[0, 0], p[1, 0]]) / (p[0, 0] + p[1, 0])  # posterior after frame 1
    f2 = -np.log(w[0] * p[0, 1] + w[1] * p[1, 1])
    out = mixture_nll(nll)
    assert np.isnan(out[0, 0])
    np.testing.assert_allclose(out[0, 1:], [f1, f2])
    # the clip's total is -log of the average evidence
    np.testing.assert_allclose(np.nansum(out), -np.log(np.mean(np.exp(-np.nansum(nll[:, 0], axis=-1)))))


def test_one_hypothesis_is_the_plain_oracle():
    nll = np.array([[[np.nan, 1.0, 2.0]]])
    np.testing.assert_allclose(mixture_nll(nll)[0, 1:], [1.0, 2.0])


def test_grid_restitutions_never_exceed_one():
    assert max(ELASTICITY_GRID) == 1.0 and min(ELASTICITY_GRID) > 0


def _batch(recs) -> Batch:
    return Batch(np.stack([r.frames for r in recs]), np.stack([r.states for r in recs]),
                 np.stack([r.present for r in recs]), FEATURE_NAMES, 0.05, tuple(r.geometry for r in recs))


@pytest.fixture(scope="module")
def energy_sets():
    c = get_concept("energy")
    return [c.make_set(i, 3, SimConfig(size=32)) for i in range(6)]


def test_infers_elasticity_from_the_first_bounce(energy_sets):
    """A ball of unknown elasticity: its later bounces cost less than under a single wrong guess."""
    mixture, fixed = PhysicsOracle(), PhysicsOracle(elasticity=0.3)
    for m in energy_sets:
        b = _batch([m.clips[0].rec])
        assert np.nansum(mixture.frame_nll(b)) < np.nansum(fixed.frame_nll(b))


def test_finds_the_too_high_bounce_more_surprising(energy_sets):
    oracle = PhysicsOracle()
    for m in energy_sets:
        pos, imp = (cl.rec for cl in m.clips[:2])
        nll = oracle.frame_nll(_batch([pos, imp]))
        assert np.nansum(nll[1]) > np.nansum(nll[0]), m.set_index


def test_a_clips_surprise_does_not_depend_on_its_batch(energy_sets):
    """Each clip refines its own hypotheses (voe.models.hypotheses), so batching changes nothing."""
    oracle = PhysicsOracle()
    recs = [cl.rec for m in energy_sets[:2] for cl in m.clips]
    together = oracle.frame_nll(_batch(recs))
    alone = np.concatenate([oracle.frame_nll(_batch([r])) for r in recs])
    np.testing.assert_array_equal(together, alone)


def test_calibration_scores_each_object_under_its_best_hypothesis(energy_sets):
    oracle = PhysicsOracle()
    noise = oracle.calibrate(_batch([m.clips[0].rec for m in energy_sets]))
    # followed frame by frame from its best hypothesis, a ball is predicted within a cell
    assert noise.sigma[0] < 0.01 and noise.sigma[1] < 0.01
    assert all(v >= f for v, f in zip(noise.sigma_return, sl.RETURN_FLOOR, strict=True))
