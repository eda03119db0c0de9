"""Fuzzed checkpoints (config.json, weights.safetensors) and controls YAML files."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from voe.controls.spec import load_user_controls
from voe.models.loading import load_model

from .mutate import FUZZ, damaged_bytes, damaged_doc, damaged_json, json_values, lay_out, only_voe_errors

CONTROLS = {"controls": [{"name": "mine", "model": "constvel", "args": {"sigma": 0.1}, "checkpoint": "ck",
                          "should_fail": ["solidity"], "should_pass": ["permanence", "gravity"],
                          "should_be_chance": ["energy"], "default": "none", "why": "a test"}]}


@pytest.fixture(scope="module")
def checkpoint(tmp_path_factory) -> dict[str, bytes]:
    """A tiny trained mlp checkpoint (weights) as {file: bytes}."""
    from voe.models.train import TrainConfig, train
    from voe.sim.scene import SimConfig
    from voe.world.generate import generate_world

    root = tmp_path_factory.mktemp("fuzzck")
    generate_world(root / "w", 8, 0, SimConfig(size=32, n_frames=12))
    train("mlp", root / "w", root / "ck", TrainConfig(steps=2, seed=0, val_frac=0.25))
    return {p.name: p.read_bytes() for p in (root / "ck").iterdir()}


def _use(files: dict[str, bytes], root: Path) -> None:
    load_model("mlp", None, lay_out(files, root / "ck"))


def test_base_checkpoint_loads(checkpoint, scratch):
    _use(checkpoint, scratch)


@FUZZ
@given(data=st.data())
def test_checkpoint_config(checkpoint, scratch, data):
    files = dict(checkpoint, **{"config.json": data.draw(damaged_json(json.loads(checkpoint["config.json"])))})
    only_voe_errors(lambda: _use(files, scratch))


@FUZZ
@given(data=st.data())
def test_checkpoint_weights(checkpoint, scratch, data):
    files = dict(checkpoint, **{"weights.safetensors": data.draw(damaged_bytes(checkpoint["weights.safetensors"]))})
    only_voe_errors(lambda: _use(files, scratch))


@FUZZ
@given(data=st.data())
def test_controls_yaml(scratch, data):
    import yaml

    p = scratch / "controls.yaml"
    if data.draw(st.booleans()):
        doc = data.draw(damaged_doc(CONTROLS)) if data.draw(st.booleans()) else data.draw(json_values)
        try:
            p.write_text(yaml.safe_dump(doc, allow_unicode=True))
        except (ValueError, yaml.YAMLError, UnicodeEncodeError):
            p.write_bytes(b"controls: [")
    else:
        p.write_bytes(data.draw(damaged_bytes(yaml.safe_dump(CONTROLS).encode())))
    only_voe_errors(lambda: load_user_controls(p))
