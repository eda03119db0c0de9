"""Scoring a probe set: stored files, the model contract, and end-to-end metrics of fake models."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from voe.errors import ModelContractError
from voe.io.probeset import load_probe_set
from voe.scoring import load_run, load_runs
from voe.scoring.score import score_probe_set
from voe.scoring.table import concept_table, condition_table
from voe.testing import BlindModel

from .conftest import N_SETS


def test_run_files(fake_runs, synth_probes):
    run = load_run(fake_runs["blind"])
    ps = load_probe_set(synth_probes)
    N, T = len(ps), ps.manifest["n_frames"]
    frames = pd.read_parquet(fake_runs["blind"] / "frames.parquet")
    assert list(frames.columns) == ["clip_id", "t", "nll"] and len(frames) == N * T
    assert run.nll.shape == (N, T) and np.isnan(run.nll[:, 0]).all() and (run.nll[:, 1:] == 1.0).all()
    clips = run.clips
    for col in ("clip_id", "concept", "set_id", "set_kind", "variant", "role", "onset_frame",
                "visible_violation", "n_distractors", "sum", "max", "mean_post", "n_scored"):
        assert col in clips.columns
    assert (clips["n_scored"] == T - 1).all() and (clips["sum"] == T - 1).all()
    assert (clips["mean_post"] == 1.0).all() and (clips["max"] == 1.0).all()
    meta = json.loads((fake_runs["blind"] / "run.json").read_text())
    assert meta["model"]["name"] == "blind" and meta["model"]["ref"] == "voe.testing:BlindModel"
    assert meta["probes"]["manifest_sha256"] == ps.manifest_sha256
    assert not meta["probes"]["path"].startswith("/")  # relative to the run: portable, no machine layout
    assert (fake_runs["blind"] / meta["probes"]["path"]).resolve() == synth_probes.resolve()
    assert "numpy" in meta["versions"] and meta["wall_time_s"] >= 0 and meta["voe_version"]


def test_fake_models_end_to_end(fake_runs):
    runs = load_runs([fake_runs[k] for k in ("cheating", "blind", "pixel-sum", "random-0")])
    t = concept_table(runs).set_index("model")
    assert (t["n_sets"] == N_SETS).all() and len(t) == 4 * 2  # 2 concepts
    t = t[t["concept"] == "Permanence-v1"]
    assert t.loc["cheating", "accuracy"] == 1.0 and t.loc["cheating", "auroc"] == 1.0
    assert t.loc["cheating", "p_value"] == 2.0 ** -N_SETS and t.loc["cheating", "verdict"] == "learned"
    for null in ("blind", "pixel-sum"):  # ties everywhere -> exactly chance, never "learned"
        assert t.loc[null, "accuracy"] == 0.5 and (t.loc[null, "ci_low"], t.loc[null, "ci_high"]) == (0.5, 0.5)
        assert t.loc[null, "verdict"] == "not learned" and t.loc[null, "p_value"] == 1.0
    assert t.loc["blind", "auroc"] == 0.5 and t.loc["blind", "pair_acc_max"] == 0.5
    cond = condition_table(runs)
    assert set(cond["condition"]) >= {"visible", "occluded"}
    assert (cond.loc[cond["model"] == "cheating", "accuracy"] == 1.0).all()


class _Bad:
    observation = "frames"

    def __init__(self, kind: str) -> None:
        self.name, self.kind = f"bad-{kind}", kind

    def frame_nll(self, batch):
        out = np.ones(batch.shape)
        if self.kind == "shape":
            return out[:, 1:]
        if self.kind == "inf":
            out[1, 5] = np.inf
        if self.kind == "hole":
            out[1, 5] = np.nan
        if self.kind == "allnan":
            out[1] = np.nan
        return out


@pytest.mark.parametrize("kind,needle", [("shape", "shape"), ("inf", "infinite"),
                                         ("hole", "warm-up prefix"), ("allnan", "no scored frame")])
def test_contract_violations_name_model_and_clip(synth_probes, tmp_path, kind, needle):
    with pytest.raises(ModelContractError, match=needle) as exc:
        score_probe_set(_Bad(kind), synth_probes, tmp_path / "run", batch_size=4)
    assert f"bad-{kind}" in str(exc.value)
    if kind != "shape":  # the clip is named by its opaque key and, for the user, its id
        assert re.search(r"clip [0-9a-f]{16} \(clip (permanence|inertia)-\d{4}-\w+\)", str(exc.value))
    assert not (tmp_path / "run").exists()  # nothing half-written


def test_batch_size_does_not_change_results(synth_probes, tmp_path, fake_runs):
    from voe.testing import RandomModel

    score_probe_set(RandomModel(), synth_probes, tmp_path / "r1", batch_size=1)
    a = pd.read_parquet(tmp_path / "r1" / "frames.parquet")
    b = pd.read_parquet(fake_runs["random-0"] / "frames.parquet")
    pd.testing.assert_frame_equal(a, b)


def test_cli_score(synth_probes, tmp_path):
    pytest.importorskip("voe.models.loading", reason="voe.models.loading (load_model) not written yet")
    out = tmp_path / "run"
    res = subprocess.run([sys.executable, "-m", "voe", "score", "--probes", str(synth_probes), "--model",
                          "voe.testing:BlindModel", "--model-arg", "value=2.5", "--batch-size", "7",
                          "--out", str(out)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    run = load_run(out)
    assert run.meta["model"]["args"] == {"value": 2.5} and run.meta["batch_size"] == 7
    assert np.nanmax(run.nll) == 2.5
    res = subprocess.run([sys.executable, "-m", "voe", "score", "--probes", str(tmp_path / "nope"),
                          "--model", "voe.testing:BlindModel", "--out", str(tmp_path / "r2")],
                         capture_output=True, text=True)
    assert res.returncode == 1 and res.stderr.startswith("voe: error:")
    assert len(res.stderr.strip().splitlines()) == 1


def test_blind_model_in_library_api(synth_probes, tmp_path):
    meta = score_probe_set(BlindModel(value=3.0, warmup=2), synth_probes, tmp_path / "b")
    assert meta["model"]["args"] == {} and meta["probes"]["n_clips"] == (4 + 2) * N_SETS
    assert (load_run(tmp_path / "b").clips["n_scored"] == meta["probes"]["n_frames"] - 2).all()


def test_cli_score_wiring_with_stub_loader(synth_probes, tmp_path, monkeypatch):
    """`voe score` passes ref, args and checkpoint to load_model and stores them (stub loader)."""
    import importlib
    import types

    from typer.testing import CliRunner

    from voe.cli.main import app

    calls = []

    def load_model(ref, args=None, checkpoint=None):
        calls.append((ref, args, checkpoint))
        mod, _, attr = ref.partition(":")
        return getattr(importlib.import_module(mod), attr)(**(args or {}))

    monkeypatch.setitem(sys.modules, "voe.models.loading", types.SimpleNamespace(load_model=load_model))
    ckpt = tmp_path / "w.bin"
    ckpt.write_bytes(b"weights")
    res = CliRunner().invoke(app, ["score", "--probes", str(synth_probes), "--model", "voe.testing:BlindModel",
                                   "--model-arg", "value=2", "--checkpoint", str(ckpt), "--out", str(tmp_path / "run"),
                                   "--no-cache"])
    assert res.exit_code == 0, res.output
    assert calls == [("voe.testing:BlindModel", {"value": 2}, ckpt)]
    meta = load_run(tmp_path / "run").meta["model"]
    assert meta["ref"] == "voe.testing:BlindModel" and meta["args"] == {"value": 2}
    assert meta["checkpoint_sha256"] == "9a129038d9a00aed0cf6a7ea059ca50a813449061ab87848cf1a13eafdf33b2c"
