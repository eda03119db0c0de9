"""Fuzzed gap-finder inputs: scene.json and recordings (csv and parquet)."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from voe.gap.recordings import load_recordings
from voe.gap.scene import load_scene

from ..gap.conftest import flight_episodes, to_table
from .mutate import FUZZ, damaged_bytes, damaged_frame, damaged_json, only_voe_errors, parquet_bytes

SCENE = {"units": {"length": "m"}, "gravity": [0, -9.81],
         "bodies": [{"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "friction": 0.5, "elasticity": 0.5},
                    {"name": "box", "shape": "box", "size": [0.2, 0.1], "mass": 2.0},
                    {"name": "arm", "shape": "poly", "vertices": [[0, 0], [0.1, 0], [0, 0.1]], "mass": 0.5}],
         "statics": [{"shape": "segment", "a": [-5, 0], "b": [5, 0], "radius": 0.01, "friction": 0.8, "elasticity": 0.3}],
         "joints": [{"type": "pivot", "a": "arm", "b": None, "anchor": [0, 1]}]}


@pytest.fixture(scope="module")
def recordings():
    scene, eps = flight_episodes(n=2, duration=0.3)
    sp_path = Path(__file__).parent / "_unused"
    del sp_path
    return scene, to_table(scene, eps)


def test_base_scene_loads(scratch):
    (scratch / "scene.json").write_text(json.dumps(SCENE))
    load_scene(scratch / "scene.json")


@FUZZ
@given(data=st.data())
def test_scene_json(scratch, data):
    p = scratch / "scene.json"
    p.write_bytes(data.draw(damaged_json(SCENE)))
    only_voe_errors(lambda: load_scene(p))


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
@FUZZ
@given(data=st.data())
def test_recordings(scratch, recordings, suffix, data):
    scene, table = recordings
    p = scratch / f"rec{suffix}"
    if data.draw(st.booleans()):
        df = data.draw(damaged_frame(table))
        if suffix == ".csv":
            p.write_text(df.to_csv(index=False))
        else:
            p.write_bytes(parquet_bytes(df) or b"")
    else:
        buf = io.BytesIO()
        if suffix == ".csv":
            buf.write(table.to_csv(index=False).encode())
        else:
            table.to_parquet(buf, index=False)
        p.write_bytes(data.draw(damaged_bytes(buf.getvalue())))
    only_voe_errors(lambda: load_recordings(p, scene))
    only_voe_errors(lambda: load_recordings(p, scene, outliers="flag"))


def test_recordings_base_loads(scratch, recordings):
    scene, table = recordings
    assert len(load_recordings("<table>", scene, pd.DataFrame(table))) == 2
