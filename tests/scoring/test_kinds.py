"""Surprise kinds: nll, bound and error are stored, reported, and ranked alike; nats only for nll."""

from __future__ import annotations

import json

import numpy as np
import pytest

from voe.errors import ModelContractError
from voe.scoring import load_run
from voe.scoring.score import score_probe_set
from voe.scoring.table import concept_table
from voe.testing import BlindModel, CheatingModel


def test_kind_is_stored_and_ranks_work_for_every_kind(synth_probes, tmp_path):
    tables = {}
    for kind in ("nll", "bound", "error"):
        # a tiny effect: 1e-5 per frame after the onset, far below the 0.01-nat tie tolerance
        meta = score_probe_set(CheatingModel(synth_probes, jump=1e-5, surprise_kind=kind), synth_probes,
                               tmp_path / kind)
        assert meta["surprise_kind"] == kind
        assert json.loads((tmp_path / kind / "run.json").read_text())["surprise_kind"] == kind
        run = load_run(tmp_path / kind)
        assert run.surprise_kind == kind
        tables[kind] = concept_table([run], n_boot=200).set_index("concept")
    # in nats, 1e-4 nats over a clip is a tie by design; a bound or an error has its own scale
    assert (tables["nll"]["accuracy"] == 0.5).all()
    for kind in ("bound", "error"):
        t = tables[kind]
        assert (t["accuracy"] == 1.0).all() and (t["auroc"] == 1.0).all() and (t["verdict"] == "learned").all()
        assert t["relative_surprise"].isna().all()  # needs calibrated nats
    assert tables["nll"]["relative_surprise"].notna().all()


def test_unknown_kind_is_refused(synth_probes, tmp_path):
    model = BlindModel()
    model.surprise_kind = "logits"
    with pytest.raises(ModelContractError, match="surprise_kind 'logits' is not one of"):
        score_probe_set(model, synth_probes, tmp_path / "r")
    assert not (tmp_path / "r").exists()


def test_report_prints_the_kind(synth_probes, tmp_path):
    from voe.report.build import build_report

    score_probe_set(CheatingModel(synth_probes, surprise_kind="error"), synth_probes, tmp_path / "err")
    score_probe_set(BlindModel(), synth_probes, tmp_path / "blind")
    s = build_report([tmp_path / "err", tmp_path / "blind"], tmp_path / "rep", n_boot=200)
    md = (tmp_path / "rep" / "report.md").read_text()
    models = md[md.index("## Models"):md.index("## Which model")]
    assert "surprise" in models and "| error" in models and "| nll" in models
    assert "| check" in models and "| skipped" in models  # scored through the Python API, unchecked
    rel = s.set_index("model")["relative_surprise"]
    assert np.isnan(rel["cheating"]).all() and not np.isnan(rel["blind"]).any()
