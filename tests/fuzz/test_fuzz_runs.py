"""Fuzzed runs: run.json, clips.parquet and frames.parquet, read as a report reads them."""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from voe.concepts import CONCEPTS
from voe.concepts.generate import generate_probe_set
from voe.scoring.runs import load_runs
from voe.scoring.score import score_probe_set
from voe.scoring.table import concept_table
from voe.sim.scene import SimConfig
from voe.testing import RandomModel

from .mutate import FUZZ, damaged_bytes, damaged_frame, damaged_json, lay_out, only_voe_errors, parquet_bytes


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> dict[str, bytes]:
    """A run of a random model on a two-concept, four-set probe set, as {file: bytes}."""
    root = tmp_path_factory.mktemp("fuzzrun")
    generate_probe_set(root / "p", CONCEPTS.ids()[:2], 2, 0, SimConfig(n_frames=40, size=32))
    score_probe_set(RandomModel(), root / "p", root / "run")
    out = root / "run"
    return {p.name: p.read_bytes() for p in out.iterdir()}


def use(files: dict[str, bytes], root: Path) -> None:
    concept_table(load_runs([lay_out(files, root / "run")]), n_boot=20)


def test_base_is_readable(base, scratch):
    use(base, scratch)


@FUZZ
@given(data=st.data())
def test_run_json(base, scratch, data):
    files = dict(base, **{"run.json": data.draw(damaged_json(json.loads(base["run.json"])))})
    only_voe_errors(lambda: use(files, scratch))


@pytest.mark.parametrize("name", ["clips.parquet", "frames.parquet"])
@FUZZ
@given(data=st.data())
def test_parquet(base, scratch, name, data):
    import io

    if data.draw(st.booleans()):
        blob = parquet_bytes(data.draw(damaged_frame(pd.read_parquet(io.BytesIO(base[name])))))
    else:
        blob = data.draw(damaged_bytes(base[name]))
    files = dict(base, **{name: blob or b""})
    only_voe_errors(lambda: use(files, scratch))
