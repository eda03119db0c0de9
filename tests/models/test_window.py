"""WindowPredictorAdapter: hand-worked errors, both declared variants, causality, a transformers model."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from voe.io.batch import Batch
from voe.models.adapters import WindowPredictorAdapter
from voe.models.check import check_model


def _flat_batch(values: list[list[int]]) -> Batch:
    """Clips whose frame t is a uniform 4x4 image of brightness ``values[b][t]``."""
    v = np.asarray(values, dtype=np.uint8)  # (B, T)
    frames = np.broadcast_to(v[:, :, None, None], v.shape + (4, 4)).copy()
    B, T = v.shape
    return Batch(frames=frames, states=np.zeros((B, T, 1, 2), np.float32),
                 present=np.zeros((B, T, 1), bool), feature_names=("x", "y"), dt=0.05,
                 clip_ids=tuple(f"k{i}" for i in range(B)), seeds=(0,) * B)


def mean_of_last(x):  # (N, k, H, W, C) -> (N, 1): brightness of the clip's last frame
    return x[:, -1].mean(axis=(1, 2, 3))[:, None]


def persist(z, h):  # (N, 1) -> (N, h, 1): nothing changes
    return np.repeat(z[:, None], h, axis=1)


def test_hand_worked_avg_and_max_over_windows():
    avg, mx = WindowPredictorAdapter.variants(mean_of_last, persist, context=1, stride=1, horizon=2)
    assert (avg.name, mx.name, avg.surprise_kind) == ("window-avg", "window-max", "error")
    b = _flat_batch([[0, 51, 153, 255]])  # brightness 0, 0.2, 0.6, 1.0
    # frame 1: only the window from frame 0 (|0.2 - 0|); frame 2: from frame 1 (0.4) and frame 0
    # (0.6); frame 3: from frame 2 (0.4) and frame 1 (0.8)
    np.testing.assert_allclose(avg.frame_nll(b)[0], [np.nan, 0.2, 0.5, 0.6], atol=1e-6)
    np.testing.assert_allclose(mx.frame_nll(b)[0], [np.nan, 0.2, 0.6, 0.8], atol=1e-6)


def test_stride_and_context():
    one = WindowPredictorAdapter(mean_of_last, persist, context=2, stride=2)  # windows at c = 2, 4
    b = _flat_batch([[0, 0, 51, 102, 102, 255]])
    # c=2 predicts frames 2, 3 from frame 1 (0.0); c=4 predicts frames 4, 5 from frame 3 (0.4)
    np.testing.assert_allclose(one.frame_nll(b)[0], [np.nan, np.nan, 0.2, 0.4, 0.0, 0.6], atol=1e-6)
    with pytest.raises(ValueError, match="horizon >= stride"):
        WindowPredictorAdapter(mean_of_last, persist, context=2, stride=3, horizon=2)


def test_surprise_depends_on_the_past_only(tiny_batch):
    model = WindowPredictorAdapter(mean_of_last, persist, context=3, stride=2, horizon=3)
    full = model.frame_nll(tiny_batch)
    t = 9
    frames = tiny_batch.frames.copy()
    frames[:, t:] = 255 - frames[:, t:]
    later = model.frame_nll(dataclasses.replace(tiny_batch, frames=frames))
    np.testing.assert_array_equal(full[:, :t], later[:, :t])
    assert not np.allclose(full[:, t:], later[:, t:])
    check_model(model, tiny_batch)


def test_tiny_transformers_video_model_passes_check_model(tiny_batch):
    torch = pytest.importorskip("torch")
    transformers = pytest.importorskip("transformers")
    cfg = transformers.VideoMAEConfig(image_size=32, patch_size=8, num_channels=1, num_frames=4,
                                      tubelet_size=2, hidden_size=16, num_hidden_layers=1,
                                      num_attention_heads=2, intermediate_size=32)
    torch.manual_seed(0)
    encoder = transformers.VideoMAEModel(cfg).eval()  # random weights, built from the config
    head = torch.nn.Linear(16, 16 * 2).eval()  # predicts 2 future token maps from the context's

    @torch.no_grad()
    def encode(x):  # (N, 4, 32, 32, 1) -> (N, tokens, 16)
        pixel_values = torch.from_numpy(x).permute(0, 1, 4, 2, 3)  # (N, T, C, H, W)
        return encoder(pixel_values=pixel_values).last_hidden_state

    @torch.no_grad()
    def predict(z, h):  # (N, tokens, 16) -> (N, h, tokens, 16)
        out = head(torch.as_tensor(z, dtype=torch.float32))  # (N, tokens, 32)
        return out.reshape(*out.shape[:2], 2, 16).permute(0, 2, 1, 3)[:, :h]

    for model in WindowPredictorAdapter.variants(encode, predict, context=4, stride=1, horizon=2,
                                                 name="videomae-tiny"):
        check_model(model, tiny_batch)  # shapes, determinism, order, batch size, causality
        s = model.frame_nll(tiny_batch)
        assert np.isnan(s[:, :4]).all() and np.isfinite(s[:, 4:]).all() and (s[:, 4:] > 0).all()
