"""Reports and provenance name inputs by sha256 and relative paths; absolute paths only on request."""

from __future__ import annotations

import json

from typer.testing import CliRunner

from voe.cli.main import app
from voe.scoring.score import score_probe_set
from voe.testing import RandomModel


def test_report_shows_no_absolute_path_unless_asked(tiny_probes, tmp_path):
    run = tmp_path / "runs" / "random"
    score_probe_set(RandomModel(), tiny_probes, run)
    meta = json.loads((run / "run.json").read_text())
    assert not meta["probes"]["path"].startswith("/")            # relative to the run directory
    for show, out in ((False, tmp_path / "rep"), (True, tmp_path / "rep-paths")):
        args = ["report", str(run), "--out", str(out)] + (["--show-paths"] if show else [])
        res = CliRunner().invoke(app, args)
        assert res.exit_code == 0, res.output
        text = "".join((out / f).read_text() for f in ("report.md", "report.html", "summary.csv"))
        assert (str(tiny_probes.resolve()) in text) == show
        assert ("/tmp/" in text) == show and "/home/" not in text and "/root/" not in text
        assert meta["probes"]["manifest_sha256"][:16] in text       # named by its manifest hash


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
