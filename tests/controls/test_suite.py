"""``voe validate-suite`` end to end on a tiny suite, user controls, and the matrix's rule."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
from typer.testing import CliRunner

from voe.cli.main import app
from voe.concepts.generate import generate_probe_set
from voe.controls.matrix import outcome_ok
from voe.controls.spec import load_user_controls
from voe.errors import UnknownNameError, VoeError
from voe.scoring.verdict import INCONCLUSIVE, LEARNED, NOT_LEARNED
from voe.sim.scene import SimConfig
from voe.world.generate import generate_world


@pytest.fixture(scope="module")
def tiny(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("suite")
    generate_probe_set(root / "probes", ["Permanence-v2", "Gravity-v4"], 4, 3, SimConfig(size=32))
    generate_world(root / "world", 30, 3, SimConfig(size=32))
    (root / "mine.yaml").write_text(
        "controls:\n"
        "  - name: my-constvel\n"
        "    model: constvel\n"
        "    should_pass: [permanence]\n"
        "    should_fail: [gravity]\n")
    return root


def test_matrix_from_the_cli_with_a_user_control_in_two_processes(tiny):
    out = tiny / "report"
    res = CliRunner().invoke(app, ["validate-suite", "--probes", str(tiny / "probes"), "--world",
                                   str(tiny / "world"), "--work", str(tiny / "work"), "--out", str(out),
                                   "--family", "knowledge-free", "--controls", str(tiny / "mine.yaml"),
                                   "--jobs", "2"])
    assert res.exit_code == 0, res.output
    m = pd.read_csv(out / "matrix.csv")
    assert set(m["control"]) == {"density", "motion-energy", "height", "speed", "stress-frame", "stress-step",
                                 "my-constvel"}
    assert set(m["concept"]) == {"Permanence-v2", "Gravity-v4"}
    from voe.io.probeset import load_probe_set

    assert set(m["condition"]) == {"all", *load_probe_set(tiny / "probes").index["condition"]}
    # single-frame scorers tie exactly on the spliced quadruplets, and those cells could not fail
    fo = m[m["control"].isin(["density", "stress-frame"]) & m["concept"].eq("Permanence-v2")]
    assert (fo["accuracy"] == 0.5).all() and fo["as_declared"].all() and not fo["could_fail"].any()
    assert "cells that could have failed" in res.output and "could not fail (by construction)" in res.output
    assert (out / "confounds.csv").exists()
    mine = m[(m["control"] == "my-constvel") & (m["condition"] == "all")].set_index("concept")
    assert mine.loc["Permanence-v2", "expected"] == "pass" and mine.loc["Gravity-v4", "expected"] == "fail"
    assert (out / "validity.md").read_text().count("Is the suite valid?") == 1
    assert (out / "figures" / "specificity.png").stat().st_size > 1000
    # a second run reuses every stored run instead of rescoring
    res = CliRunner().invoke(app, ["validate-suite", "--probes", str(tiny / "probes"), "--world",
                                   str(tiny / "world"), "--work", str(tiny / "work"), "--out", str(out),
                                   "--family", "knowledge-free", "--controls", str(tiny / "mine.yaml")])
    assert res.exit_code == 0 and res.output.count("reusing the stored run") == 1


def test_bad_user_controls_get_one_line_errors(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("controls:\n  - name: x\n    model: constvel\n    should_fail: [gravty]\n")
    with pytest.raises(UnknownNameError, match=r"bad.yaml: control 'x': unknown concept 'gravty'; did you mean 'Gravity-v4'"):
        load_user_controls(bad)
    bad.write_text("controls: []\n")
    with pytest.raises(VoeError, match="non-empty list"):
        load_user_controls(bad)
    bad.write_text("controls:\n  - model: constvel\n")
    with pytest.raises(VoeError, match="'name' and 'model'"):
        load_user_controls(bad)
    res = subprocess.run([sys.executable, "-m", "voe", "validate-suite", "--controls", str(tmp_path / "missing.yaml")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 1
    assert res.stderr.strip().splitlines() == [f"voe: error: controls file {tmp_path / 'missing.yaml'} does not exist"]


def test_probes_and_world_of_different_sizes_are_refused_in_one_line(tiny, tmp_path):
    generate_world(tmp_path / "w64", 4, 3, SimConfig(size=64))
    res = subprocess.run([sys.executable, "-m", "voe", "validate-suite", "--probes", str(tiny / "probes"),
                          "--world", str(tmp_path / "w64"), "--work", str(tmp_path / "work"),
                          "--out", str(tmp_path / "out"), "--family", "knowledge-free"],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 1
    assert res.stderr.count("\n") == 1 and "frames but probe set" in res.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(("expect", "verdict", "lo", "hi", "ok"), [
    ("pass", LEARNED, 0.7, 1.0, True), ("pass", INCONCLUSIVE, 0.4, 0.9, False),
    ("fail", NOT_LEARNED, 0.0, 0.6, True), ("fail", INCONCLUSIVE, 0.4, 0.9, False),
    ("chance", NOT_LEARNED, 0.3, 0.7, True), ("chance", NOT_LEARNED, 0.0, 0.2, False),
    ("none", LEARNED, 0.7, 1.0, None)])
def test_a_cell_is_as_declared_only_when_its_verdict_says_so(expect, verdict, lo, hi, ok):
    assert outcome_ok(expect, verdict, lo, hi) is ok
