"""Reports built from tiny stored runs: files, numbers, figures, and refusal of bad runs."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import textwrap

import pandas as pd
import pytest

from voe.errors import RunError
from voe.report.build import build_report
from voe.scoring.score import score_probe_set
from voe.testing import BlindModel, CheatingModel

from .conftest import N_SETS

REQUIRED = ["model", "concept", "n_sets", "accuracy", "ci_low", "ci_high", "p_value", "verdict"]


@pytest.fixture(scope="module")
def report(fake_runs, tmp_path_factory):
    out = tmp_path_factory.mktemp("rep") / "tiny"
    build_report([fake_runs[k] for k in ("cheating", "blind", "random-0", "pixel-sum")], out)
    return out


def test_report_files_and_numbers(report):
    for name in ("report.md", "report.html", "summary.csv", "conditions.csv",
                 "figures/accuracy_heatmap.png", "figures/accuracy_by_condition.png",
                 "figures/looking_time_cheating.png", "figures/filmstrip_permanence.png",
                 "figures/filmstrip_inertia.png"):
        assert (report / name).is_file(), name
    s = pd.read_csv(report / "summary.csv")
    assert list(s.columns[:8]) == REQUIRED
    assert {"p_holm", "relative_surprise", "pair_acc_max", "auroc"} <= set(s.columns)
    assert len(s) == 4 * 2 and (s["n_sets"] == N_SETS).all()
    s = s.set_index(["model", "concept"])
    for c in ("Permanence-v1", "Inertia-v1"):
        assert s.loc[("cheating", c), "accuracy"] == 1.0 and s.loc[("cheating", c), "verdict"] == "learned"
        # Holm over 2 concepts: 2 * 2**-6
        assert s.loc[("cheating", c), "p_holm"] == pytest.approx(2 * 2.0 ** -N_SETS)
        assert s.loc[("blind", c), "accuracy"] == 0.5 and s.loc[("blind", c), "verdict"] == "not learned"
    # spliced quadruplets: a frame-only scorer ties exactly
    assert s.loc[("pixel-sum", "Permanence-v1"), "accuracy"] == 0.5


def test_report_text_and_embedding(report):
    md = (report / "report.md").read_text()
    html = (report / "report.html").read_text()
    for needle in ("Concepts tested", "How to read", "Verdict rule", "permanence", "inertia",
                   "Looking time", "Accuracy by condition", "Example matched sets"):
        assert needle in md and needle in html
    for link in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md):
        assert (report / link).is_file(), link
    srcs = re.findall(r'<img src="([^"]+)"', html)
    assert len(srcs) == len(list((report / "figures").glob("*.png"))) == 8
    assert all(s.startswith("data:image/png;base64,") for s in srcs)
    assert not re.search(r'(src|href)="(?!data:)', html)  # self-contained


def test_report_never_imports_sim_models_or_torch(fake_runs, tmp_path):
    code = textwrap.dedent(f"""
        import sys
        from voe.report.build import build_report
        build_report([{str(fake_runs['blind'])!r}], {str(tmp_path / 'r')!r}, n_boot=200)
        bad = [m for m in sys.modules if m.split('.')[0] == 'torch' or m.startswith(('voe.sim', 'voe.models'))]
        assert not bad, bad
    """)
    subprocess.run([sys.executable, "-c", code], check=True)


def _copy(run, tmp_path, name):
    dst = tmp_path / name
    shutil.copytree(run, dst)
    return dst


def test_bad_runs_are_refused(fake_runs, tmp_path):
    from tests.scoring.synth import make_probe_set

    other = make_probe_set(tmp_path / "other", n_sets=2, seed=1)
    score_probe_set(BlindModel(), other, tmp_path / "other_run")
    with pytest.raises(RunError, match="different probe sets"):
        build_report([fake_runs["cheating"], tmp_path / "other_run"], tmp_path / "r1")
    missing = _copy(fake_runs["blind"], tmp_path, "missing")
    clips = pd.read_parquet(missing / "clips.parquet")
    clips.drop(columns=["role"]).to_parquet(missing / "clips.parquet")
    with pytest.raises(RunError, match=r"lacks column.*role"):
        build_report([missing], tmp_path / "r2")
    empty = _copy(fake_runs["blind"], tmp_path, "empty")
    clips.iloc[:0].to_parquet(empty / "clips.parquet")
    with pytest.raises(RunError, match="empty"):
        build_report([empty], tmp_path / "r3")
    with pytest.raises(RunError, match="does not exist"):
        build_report([tmp_path / "nope"], tmp_path / "r4")
    for bad in ("r1", "r2", "r3", "r4"):
        assert not (tmp_path / bad).exists()  # nothing half-written

    for args in ([str(fake_runs["cheating"]), str(tmp_path / "other_run")], [str(missing)], [str(empty)]):
        res = subprocess.run([sys.executable, "-m", "voe", "report", *args, "--out", str(tmp_path / "cli")],
                             capture_output=True, text=True)
        assert res.returncode == 1, res.stderr
        lines = res.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("voe: error:"), res.stderr


def test_cli_report(fake_runs, tmp_path):
    out = tmp_path / "cli"
    res = subprocess.run([sys.executable, "-m", "voe", "report", str(fake_runs["cheating"]),
                          str(fake_runs["blind"]), "--out", str(out)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert "report.html" in res.stdout and (out / "summary.csv").is_file()


def test_report_from_generated_permanence_probes(tmp_path):
    """A tiny real probe set: 4 Permanence sets of 32x32 frames, scored by fakes."""
    from voe.concepts.generate import generate_probe_set
    from voe.sim.scene import SimConfig

    probes = tmp_path / "probes"
    generate_probe_set(probes, ["Permanence-v2"], 4, 0, SimConfig(size=32))
    for model in (CheatingModel(probes), BlindModel()):
        score_probe_set(model, probes, tmp_path / model.name)
    s = build_report([tmp_path / "cheating", tmp_path / "blind"], tmp_path / "rep", n_boot=500)
    s = s.set_index("model")
    assert s.loc["cheating", "accuracy"] == 1.0 and s.loc["blind", "accuracy"] == 0.5
    assert s.loc["cheating", "n_sets"] == 2  # the 2 perceptual sets of 4 carry no verdict
    assert s.loc["cheating", "p_value"] == 1 / 4  # exact: 2 sets
    assert s.loc["cheating", "verdict"] == "inconclusive"  # perfect, but 2 sets cannot prove it
    assert (tmp_path / "rep" / "figures" / "filmstrip_permanence.png").is_file()


def test_summary_is_deterministic(fake_runs, report, tmp_path):
    build_report([fake_runs[k] for k in ("cheating", "blind", "random-0", "pixel-sum")], tmp_path / "again")
    assert (tmp_path / "again" / "summary.csv").read_bytes() == (report / "summary.csv").read_bytes()


def test_concept_descriptions(tmp_path):
    from voe.report.concepts import describe

    (tmp_path / "gravity").mkdir()
    (tmp_path / "gravity" / "README.md").write_text("# Gravity-v1\n\n**Concept.** Things\nfall down.\n\nMore.\n")
    assert describe("Gravity-v1", tmp_path) == "Things fall down."
    assert describe("Energy-v1", tmp_path).startswith("Objects do not gain energy")  # built-in text
    assert describe("Nonsense-v3", tmp_path) == ""


def test_missing_probe_set_only_drops_filmstrips(fake_runs, tmp_path):
    import json

    run = _copy(fake_runs["blind"], tmp_path, "moved")
    meta = json.loads((run / "run.json").read_text())
    meta["probes"]["path"] = str(tmp_path / "gone")
    (run / "run.json").write_text(json.dumps(meta))
    build_report([run], tmp_path / "rep", n_boot=200)
    assert not list((tmp_path / "rep" / "figures").glob("filmstrip_*"))
    assert "example frames are not shown" in (tmp_path / "rep" / "report.md").read_text()


def test_a_checkpoint_stopped_by_its_time_cap_is_named_in_the_report(synth_probes, tmp_path):
    """A model whose training hit the wall-time cap is named under Models, from the run's record alone.

    Why: a demo on a loaded machine stopped `interaction` at 638 of 700 steps and its report said
    nothing. `voe score` copies the checkpoint's training record into run.json; the report shows it
    for every model and warns for the capped ones (and only for them).
    """
    from voe.models.checkpoint import save_checkpoint, training_record

    capped = save_checkpoint(tmp_path / "capped", {"model": "blind", "config": {}, "seed": 3, "steps": 638,
                                                   "steps_budget": 700, "time_capped": True, "val_nll": 18.9})
    full = save_checkpoint(tmp_path / "full", {"model": "blind", "config": {}, "seed": 3, "steps": 700,
                                               "steps_budget": 700, "time_capped": False, "val_nll": 17.2})
    assert training_record(tmp_path / "nowhere") is None
    runs = {}
    for name, ck in (("capped", capped), ("full", full)):
        runs[name] = tmp_path / f"run-{name}"
        score_probe_set(BlindModel(), synth_probes, runs[name], batch_size=5, checkpoint=ck)
    rec = json.loads((runs["capped"] / "run.json").read_text())["model"]["training"]
    assert rec == {"steps": 638, "steps_budget": 700, "time_capped": True, "val_nll": 18.9, "seed": 3}
    (tmp_path / "capped").rename(tmp_path / "gone")  # the report reads the stored record, not the checkpoint
    build_report([runs["capped"]], tmp_path / "rep-capped", n_boot=200)
    md = (tmp_path / "rep-capped" / "report.md").read_text()
    assert "638 of 700 steps (time cap); val NLL 18.90" in md
    assert "Warning: under-trained model(s)" in md and "after 638 of 700 steps" in md
    build_report([runs["full"]], tmp_path / "rep-full", n_boot=200)
    md = (tmp_path / "rep-full" / "report.md").read_text()
    assert "700 of 700 steps; val NLL 17.20" in md and "under-trained" not in md
