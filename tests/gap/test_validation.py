"""Each bad input gets one clear DataError naming the problem and the file."""

from __future__ import annotations

import json

import pandas as pd
import pytest

from voe.errors import DataError
from voe.gap.recordings import load_recordings
from voe.gap.scene import load_scene

from .conftest import BALL


def _rec(n=30):
    return pd.DataFrame({"episode": 0, "t": [k / 100 for k in range(n)], "body": "ball",
                         "x": 0.0, "y": [1 - 0.5 * 9.81 * (k / 100) ** 2 for k in range(n)], "angle": 0.0})


@pytest.fixture
def scene(tmp_path):
    p = tmp_path / "scene.json"
    p.write_text(json.dumps({"gravity": [0, -9.81], "bodies": [BALL]}))
    return load_scene(p)[0]


def _check(tmp_path, scene, df, pattern):
    p = tmp_path / "rec.csv"
    df.to_csv(p, index=False)
    with pytest.raises(DataError, match=pattern) as exc:
        load_recordings(p, scene)
    assert "rec.csv" in str(exc.value)
    assert "\n" not in str(exc.value)


def test_good_recordings_load(tmp_path, scene):
    p = tmp_path / "rec.parquet"
    _rec().to_parquet(p)
    eps = load_recordings(p, scene)
    assert len(eps) == 1 and eps[0].pose.shape == (30, 1, 3)


def test_unknown_body(tmp_path, scene):
    df = _rec()
    df.loc[3, "body"] = "bal"
    _check(tmp_path, scene, df, "unknown body 'bal'")


def test_missing_column(tmp_path, scene):
    _check(tmp_path, scene, _rec().drop(columns=["angle"]), "missing column.*angle")


def test_nan(tmp_path, scene):
    df = _rec()
    df.loc[5, "x"] = float("nan")
    _check(tmp_path, scene, df, "NaN.*'x'.*row 6")


def test_time_not_increasing(tmp_path, scene):
    df = _rec()
    df.loc[10, "t"] = df.loc[9, "t"]
    _check(tmp_path, scene, df, "time does not increase.*'ball'.*episode 0")


def test_episode_too_short(tmp_path, scene):
    _check(tmp_path, scene, _rec(5), "episode 0 is too short")


def test_scene_body_without_recordings(tmp_path):
    p = tmp_path / "scene.json"
    p.write_text(json.dumps({"gravity": [0, -9.81], "bodies": [BALL, dict(BALL, name="box2")]}))
    _check(tmp_path, load_scene(p)[0], _rec(), "scene body 'box2' has no recordings")


def test_scene_errors(tmp_path):
    p = tmp_path / "scene.json"
    p.write_text(json.dumps({"bodies": [dict(BALL, shape="blob")]}))
    with pytest.raises(DataError, match="scene.json.*shape 'blob'"):
        load_scene(p)
    p.write_text("{not json")
    with pytest.raises(DataError, match="not valid JSON"):
        load_scene(p)
    p.write_text(json.dumps({"bodies": [BALL], "joints": [{"type": "pivot", "a": "nope", "b": None, "anchor": [0, 0]}]}))
    with pytest.raises(DataError, match="unknown body 'nope'"):
        load_scene(p)
