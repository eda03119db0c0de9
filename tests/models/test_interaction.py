"""The object-centric model rolls hidden slots forward on its own predictions, causally.

What must hold: hidden objects are carried by the model's own predictions (with a variance that
grows while hidden), the loss on reappearance reaches the steps before the occlusion (training
through occlusions), and the model keeps the harness contract. Whether random networks of an
architecture sit at chance is measured on probe sets (``bench/random_nets.py``), not here.
"""

from __future__ import annotations

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from voe.io.batch import Batch  # noqa: E402
from voe.models.check import check_model  # noqa: E402
from voe.sim.scene import FEATURE_NAMES  # noqa: E402

T, HIDE, BACK = 24, 6, 16  # frames; the object is hidden on frames HIDE..BACK-1
SCREEN = {"x0": 3.0, "y0": 0.0, "x1": 6.5, "y1": 3.0}


def _clip(x0: float, vx: float, jump: float = 0.0, hide: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """One ball sliding along the floor at ``vx``, hidden on HIDE..BACK-1, shifted by ``jump``
    from BACK on. Returns states ``(T, 2, F)`` (slot 1 never present) and present ``(T, 2)``."""
    s = np.full((T, 2, len(FEATURE_NAMES)), np.nan, dtype=np.float32)
    t = np.arange(T)
    s[:, 0, :] = 0.0
    s[:, 0, 0] = x0 + vx * 0.05 * t + np.where(t >= BACK, jump, 0.0)
    s[:, 0, 1] = 1.0
    s[:, 0, 3] = vx
    s[:, 0, 6], s[:, 0, 8], s[:, 0, 9], s[:, 0, 10] = 1.0, 0.8, 0.8, 0.9
    p = np.zeros((T, 2), dtype=bool)
    p[:, 0] = True
    if hide:
        p[HIDE:BACK, 0] = False
        s[HIDE:BACK, 0] = np.nan
    return s, p


def _batch(clips: list[tuple[np.ndarray, np.ndarray]]) -> Batch:
    states, present = np.stack([c[0] for c in clips]), np.stack([c[1] for c in clips])
    B = len(clips)
    geo = {"extent": [10.0, 10.0], "occluders": [SCREEN],
           "statics": [{"a": [-20.0, 0.5], "b": [30.0, 0.5], "radius": 0.1}]}
    return Batch(np.zeros((B, T, 8, 8), np.uint8), states, present, FEATURE_NAMES, 0.05, (geo,) * B)


ARCHS = ["interaction-v2", "interaction-v3"]


def _persistent(model):
    """Set the step to constant velocity (v2: every gate open, g = 1; v3: the linear map that
    moves x, y, angle by dt times their velocity and keeps the rest): the untrained network then
    carries each slot at constant velocity; and give the Gaussian the mixture (outlier weight
    ~5e-5 instead of ~1)."""
    head = model.net.head
    with torch.no_grad():
        if head.theta.ndim == 1:
            head.theta.fill_(1.0 / head.GAIN)
        else:
            w = torch.zeros(10, 13)
            w[:, :10] = torch.eye(10)
            w[0:3, 10:13] = torch.eye(3)
            head.theta.copy_(w / head.GAIN)
        head.outlier_theta.fill_(1.5 / head.OUTLIER_GAIN)
    return model


@pytest.mark.parametrize("arch", ARCHS)
def test_hidden_objects_are_rolled_forward_and_grow_uncertain(arch):
    from voe.models.loading import load_model

    m = _persistent(load_model(arch))
    b = _batch([_clip(1.0, 3.0), _clip(1.0, 3.0, jump=1.5)])
    nll = m.frame_nll(b)  # (2, T)
    assert nll[0, BACK] < nll[1, BACK] - 5.0, "a jump behind the screen must surprise a persistent model"
    np.testing.assert_allclose(nll[0, :BACK], nll[1, :BACK])  # identical until the reappearance


@pytest.mark.parametrize("arch", ARCHS)
def test_uncertainty_grows_with_the_time_hidden(arch):
    """Reappearing exactly where expected costs more after a long occlusion than after a short
    one: the carried variance accumulates along the rollout."""
    from voe.models.loading import load_model

    m = _persistent(load_model(arch))
    long, short = _clip(1.0, 3.0), _clip(1.0, 3.0, hide=False)
    short[1][BACK - 2:BACK, 0] = False
    short[0][BACK - 2:BACK, 0] = np.nan
    nll = m.frame_nll(_batch([long, short]))
    assert nll[0, BACK] > nll[1, BACK] + 0.5, nll[:, BACK]


@pytest.mark.parametrize("arch", ARCHS)
def test_reappearance_loss_reaches_the_frames_before_the_occlusion(arch):
    """Training through occlusions: the cost of the reappearance frame depends, through every
    rolled-out hidden step, on the state observed before the object went behind the screen."""
    from voe.models.interaction import rollout_nll
    from voe.models.loading import load_model

    m = _persistent(load_model(arch))
    m.net.train()
    d = m.prepare(_batch([_clip(1.0, 3.0)]))
    d["obs"].requires_grad_(True)
    rollout_nll(m.net, d)[0, BACK].backward()
    g = d["obs"].grad[0]  # (T, K, 9)
    assert g[HIDE - 1, 0, 3].abs() > 0, "no gradient from the reappearance to the last seen velocity"
    assert g[HIDE:BACK].abs().sum() == 0  # hidden frames are not observed


def test_keeps_the_model_contract(tiny_batch):
    from voe.controls.random_nets import random_network

    check_model(random_network("interaction", 3), tiny_batch)


def test_trace_reports_the_rolled_out_prediction_of_every_step():
    """``rollout_nll(..., trace)`` (``bench/hidden_rollout.py``) returns, per step, the predicted
    mean of the next frame: a constant-velocity v3 carries the hidden ball at 3 m/s."""
    from voe.models.interaction import rollout_nll
    from voe.models.loading import load_model

    m = _persistent(load_model("interaction-v3"))
    m.net.eval()
    steps = []
    with torch.no_grad():
        rollout_nll(m.net, m.prepare(_batch([_clip(1.0, 3.0)])), steps)
    assert len(steps) == T - 1 and steps[0][0].shape == (1, 2, 9) and steps[0][1].shape == (1, 2, 9)
    x = torch.stack([s[0][0, 0, 0] for s in steps]).double().numpy()  # (T-1,) predicted x of frame t+1
    np.testing.assert_allclose(np.diff(x[HIDE:BACK]), 3.0 * 0.05, atol=1e-3)
    lv = torch.stack([s[1][0, 0, 0] for s in steps]).numpy()
    assert (np.diff(lv[HIDE:BACK - 1]) > 0).all()  # the carried variance grows while hidden


def test_frame_parts_split_each_frame_exactly_and_name_the_remembered_feature():
    """``frame_parts`` sums to ``rollout_nll`` on every frame (a random network, hidden stretch
    included); and when only the ball's brightness differs after its hidden stretch, the whole
    difference of the reappearance frame sits in the ``intensity`` part (``bench/splice_blame.py``)."""
    from voe.controls.random_nets import random_network
    from voe.models.interaction import PARTS, frame_parts, rollout_nll

    m = _persistent(random_network("interaction-v3", 1))
    a, b = _clip(1.0, 3.0), _clip(1.0, 3.0)
    b[0][BACK:, 0, 10] = 0.5  # the same ball comes back dimmer (column 10: intensity)
    d = m.prepare(_batch([a, b]))
    m.net.eval()
    with torch.no_grad():
        parts = frame_parts(m.net, d).numpy()  # (2, T, K, 11)
        total = rollout_nll(m.net, d).numpy()  # (2, T)
    assert parts.shape == (2, T, 2, len(PARTS))
    np.testing.assert_allclose(parts.sum((2, 3)), total, rtol=1e-12, atol=1e-9)
    diff = (parts[1, BACK] - parts[0, BACK]).sum(0)  # (11,) per part, slots summed
    assert abs(diff[PARTS.index("intensity")]) > 0.1
    assert np.abs(np.delete(diff, PARTS.index("intensity"))).max() < 1e-9
    np.testing.assert_allclose(parts[:, :BACK], parts[:, :BACK][::-1])  # equal before the return
