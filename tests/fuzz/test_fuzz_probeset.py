"""Fuzzed probe sets: manifest.json, index.parquet and the .npy arrays (see ``mutate``)."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from voe.concepts import CONCEPTS
from voe.concepts.generate import generate_probe_set
from voe.io.probeset import load_probe_set
from voe.io.validate import validate_probe_set
from voe.sim.scene import SimConfig

from .mutate import (
    FUZZ,
    damaged_array,
    damaged_bytes,
    damaged_frame,
    damaged_json,
    lay_out,
    only_voe_errors,
    parquet_bytes,
)


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> dict[str, bytes]:
    """A valid one-set probe set, as {relative path: bytes}, built once."""
    out = tmp_path_factory.mktemp("fuzzbase") / "set"
    generate_probe_set(out, [CONCEPTS.ids()[0]], 1, 0, SimConfig(n_frames=40, size=32))
    return {p.relative_to(out).as_posix(): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


def _write(root: Path, files: dict[str, bytes]) -> Path:
    return lay_out(files, root / "set")


def use(path: Path) -> None:
    """Everything a user does with a probe set: open, validate, read a batch."""
    ps = load_probe_set(path)
    validate_probe_set(ps)
    ids = list(ps.index["clip_id"][:2])
    ps.get(ids)
    ps.batch(ids)


def test_base_is_valid(base, scratch):
    ps = load_probe_set(_write(scratch, base))
    assert validate_probe_set(ps).ok


@FUZZ
@given(data=st.data())
def test_manifest(base, scratch, data):
    files = dict(base)
    files["manifest.json"] = data.draw(damaged_json(json.loads(base["manifest.json"])))
    only_voe_errors(lambda: use(_write(scratch, files)))


@FUZZ
@given(data=st.data())
def test_index(base, scratch, data):
    files = dict(base)
    if data.draw(st.booleans()):
        df = data.draw(damaged_frame(pd.read_parquet(_write(scratch, base) / "index.parquet")))
        blob = parquet_bytes(df)
        files["index.parquet"] = blob if blob is not None else b""
    else:
        files["index.parquet"] = data.draw(damaged_bytes(base["index.parquet"]))
    only_voe_errors(lambda: use(_write(scratch, files)))


@FUZZ
@given(data=st.data())
def test_arrays(base, scratch, data):
    import io

    import numpy as np

    files = dict(base)
    name = data.draw(st.sampled_from(sorted(k for k in base if k.endswith(".npy"))))
    files[name] = data.draw(damaged_array(np.load(io.BytesIO(base[name]), allow_pickle=False)))
    only_voe_errors(lambda: use(_write(scratch, files)))
