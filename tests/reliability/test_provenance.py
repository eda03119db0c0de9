"""Reports and provenance name inputs by sha256 and relative paths; absolute paths only on request."""

from __future__ import annotations

import json

from typer.testing import CliRunner

from voe.cli.main import app
from voe.io.paths import show_path
from voe.scoring.score import score_probe_set
from voe.testing import RandomModel


def test_report_shows_no_absolute_path_unless_asked(tmp_path):
    from voe.concepts import CONCEPTS
    from voe.concepts.generate import generate_probe_set
    from voe.report.build import build_report
    from voe.sim.scene import SimConfig

    tiny_probes = tmp_path / "probes"
    generate_probe_set(tiny_probes, CONCEPTS.ids()[:1], 2, 0, SimConfig(n_frames=40, size=32))
    run = tmp_path / "runs" / "random"
    score_probe_set(RandomModel(), tiny_probes, run)
    meta = json.loads((run / "run.json").read_text())
    assert not meta["probes"]["path"].startswith("/")            # relative to the run directory
    out = tmp_path / "rep"
    build_report([run], out, n_boot=50)                            # (a report takes a while: one only)
    text = "".join((out / f).read_text() for f in ("report.md", "report.html", "summary.csv"))
    assert str(tmp_path) not in text and "/tmp/" not in text and "/home/" not in text and "/root/" not in text
    assert f"`{tiny_probes.name}` (manifest sha256 `{meta['probes']['manifest_sha256'][:16]}`" in text
    # --show-paths: the same sentence names the absolute path
    assert show_path(tiny_probes, True) == str(tiny_probes.resolve()) and show_path(tiny_probes) == tiny_probes.name
    assert "--show-paths" in CliRunner().invoke(app, ["report", "--help"]).output


def test_gap_json_names_inputs_relative_to_the_output(tmp_path):
    from voe.gap.run import diagnose

    from ..gap.conftest import BALL, flight_episodes, to_table

    spec, eps = flight_episodes(n=3, duration=1.5)
    (tmp_path / "in").mkdir()
    scene, rec = tmp_path / "in" / "scene.json", tmp_path / "in" / "rec.csv"
    scene.write_text(json.dumps({"gravity": [0, -9.81], "bodies": [BALL]}))
    to_table(spec, eps).to_csv(rec, index=False)
    diagnose(scene, rec, tmp_path / "out", effects=["linear_drag"], figures=False)
    prov = json.loads((tmp_path / "out" / "gap.json").read_text())["provenance"]["inputs"]
    assert prov["scene"]["path"] == "../in/scene.json" and prov["recordings"]["path"] == "../in/rec.csv"
    assert len(prov["recordings"]["sha256"]) == 64
    assert str(tmp_path) not in (tmp_path / "out" / "gap.json").read_text()
