"""End to end on small flight-only data: clean -> consistent, hidden drag -> found; CLI forms."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from typer.testing import CliRunner

from voe.cli.main import app
from voe.gap import GapFinder
from voe.gap.stages import GapConfig

from .conftest import flight_episodes

FEW = ("linear_drag", "quadratic_drag", "constant_acceleration", "angular_damping")


def test_clean_data_is_consistent():
    scene, eps = flight_episodes(n=6, duration=2.0, seed=5)
    f = GapFinder(effects=FEW, seed=0).fit(scene, eps)
    assert f.verdict_ == "consistent"
    assert f.effects_ == []
    assert all(x["z"] <= f.z_strong_ for x in f.located_)
    assert f.fit_["before"] == f.fit_["after"]
    # the three-way split named nothing, so the finder looked again cross-fitted and says so
    assert f.problem_.split.scheme == "cross-fitting" and f.to_dict()["episodes"]["scheme"] == "cross-fitting"
    assert f.to_dict()["second_look"]["verdict"] == "consistent" and f.first_look_["scheme"] == "three-way"
    assert "Second look" in f.explanation_


def test_only_the_second_look_answers_to_the_test_gain_bar(monkeypatch):
    import voe.gap.finder as finder

    seen = []
    monkeypatch.setattr(finder, "short_on_test", lambda c, p, config, z: seen.append(p.split.scheme) or c)
    scene, eps = flight_episodes(n=6, duration=2.0, seed=5)
    GapFinder(effects=FEW, seed=0).fit(scene, eps)  # named nothing: looked again, and the bar is asked
    assert seen == ["cross-fitting"]
    scene, eps = flight_episodes("linear_drag", [0.4], n=6, duration=2.0, seed=6)
    f = GapFinder(effects=FEW, seed=0).fit(scene, eps)  # named at once: no second look, no bar
    assert seen == ["cross-fitting"] and f.effects_[0]["name"] == "linear_drag"


def test_second_look_can_be_turned_off():
    scene, eps = flight_episodes(n=6, duration=2.0, seed=5)
    f = GapFinder(effects=FEW, seed=0, config=GapConfig(second_look=False)).fit(scene, eps)
    assert f.verdict_ == "consistent" and f.problem_.split.scheme == "three-way"
    assert f.to_dict()["second_look"] is None and "Second look" not in f.explanation_


def test_hidden_linear_drag_is_found_and_fitted():
    scene, eps = flight_episodes("linear_drag", [0.4], n=6, duration=2.0, seed=6)
    f = GapFinder(effects=FEW, seed=0).fit(scene, eps)
    assert f.verdict_ == "mismatch"
    assert f.effects_[0]["name"] == "linear_drag"
    assert abs(f.effects_[0]["params"]["c"] - 0.4) / 0.4 < 0.15
    assert f.fit_["after"] < 0.5 * f.fit_["before"]
    assert f.located_ and {x["context"] for x in f.located_} == {"flight"}
    assert "linear_drag" in f.explanation_
    assert f.first_look_ is None and f.problem_.split.scheme == "three-way"  # named at once: no second look


def test_cross_fitted_finder_selects_on_every_non_test_episode():
    scene, eps = flight_episodes("linear_drag", [0.4], n=6, duration=2.0, seed=6)
    f = GapFinder(effects=FEW, seed=0, config=GapConfig(cross_fit=True)).fit(scene, eps)
    assert f.effects_[0]["name"] == "linear_drag" and abs(f.effects_[0]["params"]["c"] - 0.4) / 0.4 < 0.15
    assert {w.ep for w in f.search_.fitter.test} == {0, 1, 2, 3, 4}  # both halves select
    assert len(f.search_.fitter.folds) == 2 and len(f.effects_[0]["interval95"]) == 1
    d = f.to_dict()
    assert d["episodes"]["scheme"] == "cross-fitting" and d["fit"]["test_episodes"] == [eps[5].id]
    assert f.fit_["after"] < 0.5 * f.fit_["before"]


def test_parallel_candidate_fits_give_the_same_diagnosis():
    scene, eps = flight_episodes("quadratic_drag", [0.15], n=4, duration=1.5, seed=7)
    one = GapFinder(effects=FEW[:3], seed=0, max_effects=2).fit(scene, eps)
    two = GapFinder(effects=FEW[:3], seed=0, max_effects=2, n_jobs=2).fit(scene, eps)
    assert one.effects_ and one.effects_[0]["name"] == "quadratic_drag"
    assert json.dumps(one.to_dict(), sort_keys=True) == json.dumps(two.to_dict(), sort_keys=True)
    assert one.problem_.shooter.n_rollouts == two.problem_.shooter.n_rollouts  # workers' rollouts are counted


def test_cli_diagnose_default_form_and_bench_help(flight_files, tmp_path):
    scene, rec = flight_files
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["gap", str(scene), str(rec), "--out", str(out), "--effects", "linear_drag"])
    assert r.exit_code == 0, r.output
    data = json.loads((out / "gap.json").read_text(), parse_constant=lambda c: pytest.fail(f"gap.json holds {c}"))
    assert data["verdict"] in ("consistent", "mismatch")
    assert set(data) >= {"verdict", "located", "effects", "fit", "explanation", "provenance", "episodes", "dropped"}
    assert data["episodes"]["scheme"] == "cross-validation" and len(data["episodes"]["folds"]) == 3  # 3 episodes
    assert all(not set(f["select"]) & set(f["test"]) for f in data["episodes"]["folds"])  # no reuse within a fold
    assert "on each cross-validation fold's test episode (one that neither fitted nor selected" in data["explanation"] \
        or data["verdict"] != "mismatch"
    assert data["fit"]["on"].startswith("each cross-validation fold's test episode")
    assert len(data["provenance"]["inputs"]["scene"]["sha256"]) == 64
    assert (out / "gap.md").exists() and (out / "trajectories.png").exists() and (out / "residual.png").exists()
    r = CliRunner().invoke(app, ["gap", "bench", "--help"])
    assert r.exit_code == 0 and "--cases" in r.output and "--noise" in r.output
    r = CliRunner().invoke(app, ["gap", "diagnose", "--help"])
    assert r.exit_code == 0 and "--max-effects" in r.output


def test_cli_reports_bad_input_as_one_line(tmp_path, flight_files):
    scene, _ = flight_files
    bad = tmp_path / "bad.csv"
    bad.write_text("episode,t,body,x,y\n0,0,ball,0,0\n")
    p = subprocess.run([sys.executable, "-m", "voe", "gap", str(scene), str(bad), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert p.returncode == 1
    assert "voe: error: recordings" in p.stderr and "missing column(s) angle" in p.stderr
