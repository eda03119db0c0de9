"""Absurd recordings are refused (non-finite, huge) or, on request, flagged per row; never silent."""

from __future__ import annotations

import json

import numpy as np
import pytest

from voe.errors import DataError
from voe.gap.bench import make_case
from voe.gap.outliers import find_outliers
from voe.gap.recordings import load_recordings
from voe.gap.scene import load_scene

from ..reliability.cli import assert_one_line_error, run_voe
from .conftest import BALL, flight_episodes, to_table


@pytest.fixture
def files(tmp_path):
    scene, eps = flight_episodes(n=2, duration=1.0)
    sp = tmp_path / "scene.json"
    sp.write_text(json.dumps({"gravity": [0, -9.81], "bodies": [BALL]}))
    return sp, to_table(scene, eps), load_scene(sp)[0]


def _load(tmp_path, spec, df, **kw):
    p = tmp_path / "rec.csv"
    df.to_csv(p, index=False)
    return load_recordings(p, spec, **kw)


@pytest.mark.parametrize("value, pattern", [(np.inf, r"non-finite 'x' \(inf\) at data row 8"),
                                            (-np.inf, r"non-finite 'x' \(-inf\) at data row 8"),
                                            (1e300, r"impossibly large 'x' \(1e\+300.*data row 8")])
def test_non_finite_and_huge_refused_naming_the_row(tmp_path, files, value, pattern):
    _, df, spec = files
    df.loc[7, "x"] = value
    with pytest.raises(DataError, match=pattern) as exc:
        _load(tmp_path, spec, df)
    assert "rec.csv" in str(exc.value) and "\n" not in str(exc.value)


def test_isolated_spike_refused_then_flagged(tmp_path, files):
    _, df, spec = files
    df.loc[40, "y"] += 3.0   # a 3 m glitch in the middle of a throw
    with pytest.raises(DataError, match=r"data row 41 \(episode 0, body 'ball', y = .*isolated spike"):
        _load(tmp_path, spec, df)
    eps = _load(tmp_path, spec, df, outliers="flag")
    assert [(o.row, o.column) for o in eps[0].outliers] == [(41, "y")]
    assert eps[1].outliers == ()
    assert eps[0].pose[40 - 0, 0, 1] == pytest.approx(df.loc[40, "y"])  # kept, not altered


def test_clean_recordings_with_impacts_are_not_flagged():
    """Bounces and box strikes (the bench's scenes) have kinks, not spikes: nothing flagged."""
    for i, truth in enumerate(("none", "restitution", "mass")):
        for noise in (1e-3, 1e-5):
            case = make_case(np.random.default_rng(100 + i), truth, noise=noise, episodes=3)
            assert find_outliers(to_table(case.scene, case.episodes), case.scene.names) == []


def test_cli_refuses_1e300_in_one_line(tmp_path, files):
    sp, df, _ = files
    df.loc[7, "x"] = 1e300
    rp = tmp_path / "rec.csv"
    df.to_csv(rp, index=False)
    proc = run_voe("gap", sp, rp, "--out", tmp_path / "out", "--no-figures")
    assert_one_line_error(proc, "rec.csv", "data row 8")
    assert not (tmp_path / "out" / "gap.json").exists()
