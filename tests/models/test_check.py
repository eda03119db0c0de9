"""check_model over every registered model, the adapters and user models."""

from __future__ import annotations

import numpy as np
import pytest

from tests.models import user_model
from voe.errors import ModelContractError
from voe.models import MODELS
from voe.models.adapters import PointPredictorAdapter, TorchDistributionAdapter
from voe.models.check import check_model
from voe.models.loading import load_model


@pytest.mark.parametrize("model_id", MODELS.ids())
def test_registered_models_keep_the_contract(model_id, tiny_batch):
    model = load_model(model_id)
    check_model(model, tiny_batch)
    out = model.frame_nll(tiny_batch)
    w = getattr(model, "warmup", 1)  # the flat MLP waits for its first full window of k frames
    assert np.isnan(out[:, :w]).all() and np.isfinite(out[:, w:]).all()


def test_point_predictor_adapter(tiny_batch):
    model = PointPredictorAdapter(lambda s, dt, names: s, name="stay")  # predicts no motion
    before = np.nanmean(model.frame_nll(tiny_batch))
    model.calibrate(tiny_batch)
    assert np.nanmean(model.frame_nll(tiny_batch)) < before  # ML noise fits better than the guess
    check_model(model, tiny_batch)


class _GaussianStates:
    """A causal module: each frame ~ N(previous frame, 1); returns a torch distribution."""

    def __new__(cls):
        import torch

        class M(torch.nn.Module):
            def forward(self, obs):
                return torch.distributions.Normal(obs[:, :-1], torch.ones_like(obs[:, :-1]))

        return M()


def test_torch_distribution_adapter(tiny_batch):
    model = TorchDistributionAdapter(_GaussianStates(), observation="states", name="gauss")
    check_model(model, tiny_batch)
    out = model.frame_nll(tiny_batch)
    K, F = tiny_batch.states.shape[2:]
    # frames that do not change at all cost exactly the Gaussian normaliser
    assert np.nanmin(out) >= K * (F + 1) * 0.5 * np.log(2 * np.pi) - 1e-6


def test_user_model_by_reference(tiny_batch):
    model = load_model("tests.models.user_model:Thing", {"scale": 3})
    check_model(model, tiny_batch)
    assert model.scale == 3.0
    assert load_model("tests.models.user_model:make_thing").scale == 2.0


@pytest.mark.parametrize("cls, what", [("WrongShape", "shape"), ("NaNInside", "NaN at clip 0, frame 5"),
                                       ("BatchDependent", "failed the batch size check")])
def test_broken_user_models_are_named(cls, what, tiny_batch):
    model = getattr(user_model, cls)()
    with pytest.raises(ModelContractError, match=what) as err:
        check_model(model, tiny_batch)
    assert "'thing'" in str(err.value)
