"""Training lowers validation NLL; checkpoints round-trip; mismatched checkpoints are refused."""

from __future__ import annotations

import json

import numpy as np
import pytest

from voe.errors import CheckpointError, ProbeSetError
from voe.io.batch import Batch
from voe.models.loading import load_model
from voe.models.train import TrainConfig, split_batches, train, val_nll


def test_training_lowers_val_nll_and_round_trips(tiny_world, tmp_path):
    _, val, _ = split_batches(tiny_world, 0.25, 0)
    untrained = val_nll(load_model("interaction", {"seed": 0}), val)
    meta = train("interaction", tiny_world, tmp_path / "ck", TrainConfig(steps=60, val_frac=0.25, eval_every=20))
    assert meta["val_nll"] < untrained - 5.0, (untrained, meta["val_nll"])
    cfg = json.loads((tmp_path / "ck" / "config.json").read_text())
    assert cfg["seed"] == 0 and len(cfg["train_manifest_sha256"]) == 64
    assert cfg["feature_layout"]["feature_names"][0] == "x"
    a = load_model("interaction", checkpoint=tmp_path / "ck").frame_nll(val)
    b = load_model("interaction-v3", checkpoint=tmp_path / "ck").frame_nll(val)
    np.testing.assert_array_equal(a, b)
    assert np.nanmean(a) == pytest.approx(meta["val_nll"], abs=1e-4)


@pytest.mark.parametrize("model", ["interaction", "mlp"])
def test_the_same_seed_and_steps_give_the_same_checkpoint(model, tiny_world, tmp_path, monkeypatch):
    """The budget is steps and the schedule follows the step count only: the wall clock (here a
    clock that jumps an hour per call) changes nothing, unless the minutes cap is hit, and
    then the checkpoint says so."""
    import time

    from safetensors.numpy import load_file

    cfg = TrainConfig(steps=6, val_frac=0.25, eval_every=3)
    train(model, tiny_world, tmp_path / "a", cfg)
    real, t = time.monotonic, [0.0]

    def jumpy() -> float:
        t[0] += 3600.0
        return real() + t[0]

    monkeypatch.setattr(time, "monotonic", jumpy)
    meta = train(model, tiny_world, tmp_path / "b", cfg)
    assert meta["steps"] == 6 and not meta["time_capped"]
    a, b = load_file(str(tmp_path / "a" / "weights.safetensors")), load_file(str(tmp_path / "b" / "weights.safetensors"))
    assert all(np.array_equal(a[k], b[k]) for k in a)
    step_s = [15.0]  # now every clock reading is 15 s later: a 1-minute cap stops the run early
    monkeypatch.setattr(time, "monotonic", lambda: real() + (step_s.append(step_s[-1] + 15.0) or step_s[-1]))
    capped = train(model, tiny_world, tmp_path / "c", TrainConfig(steps=6, minutes=1.0, val_frac=0.25, eval_every=1))
    assert capped["time_capped"] and 1 <= capped["steps"] < 6


def test_reference_calibration_round_trips(tiny_world, tmp_path):
    meta = train("constvel", tiny_world, tmp_path / "cv", TrainConfig(val_frac=0.25))
    _, val, _ = split_batches(tiny_world, 0.25, 0)
    model = load_model("constvel", checkpoint=tmp_path / "cv")
    assert val_nll(model, val) == pytest.approx(meta["val_nll"])
    assert val_nll(model, val) < val_nll(load_model("constvel"), val)


@pytest.fixture(scope="module")
def mlp_ckpt(tiny_world, tmp_path_factory):
    out = tmp_path_factory.mktemp("ck") / "mlp"
    train("mlp", tiny_world, out, TrainConfig(steps=3, val_frac=0.25))
    return out


def test_checkpoint_of_another_model_is_refused(mlp_ckpt):
    with pytest.raises(CheckpointError, match="trained for model 'mlp-v2', not 'interaction-v3'"):
        load_model("interaction", checkpoint=mlp_ckpt)


def test_checkpoint_with_other_architecture_is_refused(mlp_ckpt, tmp_path):
    with pytest.raises(CheckpointError, match="hidden"):
        load_model("mlp", {"hidden": 32}, checkpoint=mlp_ckpt)
    bad = tmp_path / "bad"
    bad.mkdir()
    cfg = json.loads((mlp_ckpt / "config.json").read_text())
    cfg["config"]["hidden"] = 32
    (bad / "config.json").write_text(json.dumps(cfg))
    (bad / "weights.safetensors").write_bytes((mlp_ckpt / "weights.safetensors").read_bytes())
    with pytest.raises(CheckpointError, match="does not fit mlp-v2"):
        load_model("mlp", checkpoint=bad)


@pytest.mark.parametrize("field, value, says", [
    ("hidden", 10 ** 12, "hidden must be an integer"), ("layers", -1, "layers must be an integer"),
    ("k", 2.5, "k must be an integer"), ("hidden", 60000, "parameters"), ("seed", True, "seed must be")])
def test_a_damaged_config_is_refused_in_one_line_before_any_memory_is_taken(mlp_ckpt, tmp_path, field, value, says):
    bad = tmp_path / "bad"
    bad.mkdir()
    cfg = json.loads((mlp_ckpt / "config.json").read_text())
    cfg["config"][field] = value
    (bad / "config.json").write_text(json.dumps(cfg))
    (bad / "weights.safetensors").write_bytes((mlp_ckpt / "weights.safetensors").read_bytes())
    with pytest.raises(CheckpointError, match=f"config.json: .*{says}") as err:
        load_model("mlp", checkpoint=bad)
    assert "\n" not in str(err.value)


def test_checkpoint_with_other_feature_layout_is_refused(mlp_ckpt, tiny_batch):
    model = load_model("mlp", checkpoint=mlp_ckpt)
    names = tuple(f"{n}_renamed" if n == "intensity" else n for n in tiny_batch.feature_names)
    other = Batch(tiny_batch.frames, tiny_batch.states, tiny_batch.present, names, tiny_batch.dt,
                  tiny_batch.geometry, tiny_batch.clip_ids)
    with pytest.raises(CheckpointError, match="feature_names"):
        model.frame_nll(other)


def test_missing_checkpoint(tmp_path):
    with pytest.raises(CheckpointError, match="does not exist"):
        load_model("mlp", checkpoint=tmp_path / "nope")


def test_empty_training_set(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.raises(ProbeSetError):
        train("mlp", tmp_path / "empty", tmp_path / "ck", TrainConfig(steps=1))


def _poisoned_nll(model, every):
    """``model.nll`` that gives NaN on every ``every``-th call (every=1: always)."""
    import torch

    clean, calls = model.nll, [0]

    def nll(d):
        out = clean(d)
        calls[0] += 1
        if model.net.training and calls[0] % every == 0:
            out = out * torch.tensor(float("nan"))
        return out

    return nll


def test_a_non_finite_batch_is_skipped_not_learned(tiny_world, tmp_path):
    # one NaN batch once turned every weight of a demo's model into NaN and a NaN checkpoint was written
    from voe.models.train import fit, split_clips

    tr, va = split_clips(tiny_world, 0.25, 0)[:2]
    model = load_model("interaction", {"seed": 0})
    model.nll = _poisoned_nll(model, 7)
    meta = fit(model, tr, va, TrainConfig(steps=30, val_frac=0.25, eval_every=10))
    assert meta["skipped_steps"] == 4 and np.isfinite(meta["val_nll"])
    for p in model.net.parameters():
        assert p.detach().isfinite().all()


def test_training_that_never_gives_a_finite_loss_fails(tiny_world):
    from voe.errors import VoeError
    from voe.models.train import fit, split_clips

    tr, va = split_clips(tiny_world, 0.25, 0)[:2]
    model = load_model("interaction", {"seed": 0})
    model.nll = _poisoned_nll(model, 1)
    with pytest.raises(VoeError, match="diverged: 11 of 11 steps had a non-finite loss"):
        fit(model, tr, va, TrainConfig(steps=30, val_frac=0.25, eval_every=10))
