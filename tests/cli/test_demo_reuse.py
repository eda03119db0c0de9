"""The demo reuses a stored checkpoint only if its training ran to its step budget."""

from __future__ import annotations

from voe.demo import reusable
from voe.models.checkpoint import save_checkpoint


def _ckpt(path, **meta):
    return save_checkpoint(path, {"model": "mlp-v2", "config": {}, **meta})


def test_missing_checkpoint_is_not_reusable(tmp_path):
    assert not reusable(tmp_path / "none", say=lambda m: None)


def test_complete_checkpoint_is_reused(tmp_path):
    assert reusable(_ckpt(tmp_path / "mlp", steps=1500, steps_budget=1500, time_capped=False), say=lambda m: None)


def test_capped_checkpoint_is_trained_again_and_says_so(tmp_path):
    said = []
    assert not reusable(_ckpt(tmp_path / "interaction", steps=478, steps_budget=700, time_capped=True), say=said.append)
    assert said and "478 of 700" in said[0] and "interaction" in said[0]
