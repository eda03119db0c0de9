"""The blind harness: shuffled order, opaque keys, CRN seeds, and cheaters that it defeats."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from voe.errors import ModelContractError
from voe.io.clipkey import clip_key
from voe.io.probeset import load_probe_set
from voe.models.check import check_model
from voe.scoring import load_run
from voe.scoring.order import Blinder, plan
from voe.scoring.score import score_probe_set
from voe.scoring.table import concept_table
from voe.testing import FuturePeekingModel, IdReaderModel, NoisyModel, PositionModel

from .synth import make_probe_set

CHEATERS = [(IdReaderModel, "identifiers"), (PositionModel, "order"), (FuturePeekingModel, "causality")]


@pytest.fixture(scope="module")
def big_probes(tmp_path_factory):
    """40 sets per concept: enough that chance and 1.00 cannot be confused."""
    return make_probe_set(tmp_path_factory.mktemp("blind") / "probes", n_sets=40, seed=3)


def test_schedule_spreads_sets_and_is_seeded(synth_probes):
    ps = load_probe_set(synth_probes)
    sched = plan(ps.index, 5, seed=0)
    flat = [c for b in sched.batches for c in b]
    assert sorted(flat) == sorted(ps.index["clip_id"]) and max(map(len, sched.batches)) == 5
    set_of = dict(zip(ps.index["clip_id"], ps.index["set_id"], strict=True))
    for b in sched.batches:  # never two clips of one matched set side by side
        assert len({set_of[c] for c in b}) == len(b)
    assert plan(ps.index, 5, seed=0) == sched and plan(ps.index, 5, seed=1).batches != sched.batches
    # the stored order (A, B, AB, BA / possible, impossible) is gone: roles by batch position
    roles = ps.index.set_index("clip_id")["role"]
    first = [roles[b[0]] for b in sched.batches]
    assert 0.2 < np.mean([r == "impossible" for r in first]) < 0.8
    # shards: whole groups, every batch exactly once, no padding
    shards = [sched.for_rank(r, 3) for r in range(3)]
    assert sorted(i for s in shards for i in s) == list(range(len(sched.batches)))


def test_batch_is_blind_with_crn_seeds(synth_probes):
    ps = load_probe_set(synth_probes)
    blinder = Blinder(ps, seed=4)
    ids = list(ps.index["clip_id"][:6])  # permanence-0000-{A,B,AB,BA}, permanence-0001-{A,B}
    batch = blinder.batch(ids)
    assert batch.clip_ids == tuple(clip_key(ps.manifest_sha256, c) for c in ids)
    assert all(len(k) == 16 and "-" not in k for k in batch.clip_ids)
    assert len(set(batch.seeds[:4])) == 1 and batch.seeds[4] == batch.seeds[5] != batch.seeds[0]
    assert Blinder(ps, seed=5).batch(ids).seeds != batch.seeds
    assert blinder.describe(batch.clip_ids[2]) == f"{batch.clip_ids[2]} (clip {ids[2]})"


@pytest.mark.parametrize("n", [2, 6])
@pytest.mark.parametrize("cls, check", CHEATERS)
def test_check_model_rejects_cheaters_by_name(cls, check, n, synth_probes):
    ps = load_probe_set(synth_probes)
    blinder = Blinder(ps)
    batch = blinder.batch(blinder.sample(plan(ps.index, n), n))
    with pytest.raises(ModelContractError, match=f"failed the {check} check") as err:
        check_model(cls(), batch)
    assert f"'{cls().name}'" in str(err.value) and "\n" not in str(err.value)



@pytest.mark.parametrize("cls", [IdReaderModel, PositionModel])
def test_cheaters_sit_at_chance_when_scored_unchecked(cls, big_probes, tmp_path):
    ps = load_probe_set(big_probes)
    # the old harness (role-bearing ids, stored order, a set's clips together) gave the answer away
    index = ps.index.sort_values("row")
    cheat = {}
    for concept, grp in index.groupby("concept"):
        wins = []
        for _, s in grp.groupby("set_id"):
            nll = cls().frame_nll(ps.batch(list(s["clip_id"]))).sum(1)
            imp = (s["role"] == "impossible").to_numpy()
            wins.append(nll[imp].mean() > nll[~imp].mean())
        cheat[concept] = np.mean(wins)
    assert min(cheat.values()) == 1.0
    # the blind harness: opaque keys, shuffled order, one clip per set per batch
    score_probe_set(cls(), ps, tmp_path / "run", batch_size=8)
    t = concept_table([load_run(tmp_path / "run")], n_boot=500).set_index("concept")
    assert (t["accuracy"].between(0.3, 0.7)).all(), t["accuracy"]
    assert (t["verdict"] != "learned").all()


def test_crn_makes_a_pure_noise_scorer_tie(synth_probes, tmp_path):
    meta = score_probe_set(NoisyModel(), synth_probes, tmp_path / "run", batch_size=5, seed=7)
    assert meta["surprise_kind"] == "bound" and meta["common_random_numbers"]["seed"] == 7
    t = concept_table([load_run(tmp_path / "run")], n_boot=200)
    assert (t["accuracy"] == 0.5).all() and (t["ci_low"] == 0.5).all()  # same noise for a set's clips


def _voe(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "voe", *argv], capture_output=True, text=True)


@pytest.mark.parametrize("cls, check", CHEATERS)
def test_cli_model_check_rejects_cheaters(cls, check, synth_probes):
    res = _voe("model", "check", f"voe.testing:{cls.__name__}", "--data", str(synth_probes))
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1, res.stderr
    assert lines[0].startswith(f"voe: error: model '{cls().name}' failed the {check} check")


def test_cli_score_checks_first_unless_told_not_to(synth_probes, tmp_path):
    argv = ("score", "--probes", str(synth_probes), "--model", "voe.testing:IdReaderModel", "--out",
            str(tmp_path / "r"), "--no-cache")
    res = _voe(*argv)
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 2 and len(lines) == 1, res.stderr
    assert lines[0].startswith("voe: error: model 'id-reader' failed the identifiers check")
    assert not (tmp_path / "r").exists()
    res = _voe(*argv, "--no-check")
    assert res.returncode == 0, res.stderr
    assert load_run(tmp_path / "r").meta["check"] == "skipped"
