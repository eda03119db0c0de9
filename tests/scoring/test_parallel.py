"""Sharded scoring (torchrun, gloo, 2 CPU ranks; job-array shards), the resumable cache, failing
models, and --device/--bf16."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from voe.errors import ModelContractError, VoeError
from voe.io.clipkey import clip_key
from voe.io.probeset import load_probe_set
from voe.scoring.order import plan
from voe.scoring.score import score_probe_set
from voe.scoring.store import VOLATILE_FIELDS
from voe.testing import BlindModel, RandomModel

ROOT = Path(__file__).resolve().parents[2]
MODEL = "voe.testing:RandomModel"


def _voe(*argv: str, tmp: Path, runner: tuple[str, ...] = ("-m", "voe")) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(tmp / "xdg")}
    return subprocess.run([sys.executable, *runner, *argv], capture_output=True, text=True, cwd=ROOT, env=env)


def _same_run(a: Path, b: Path) -> None:
    """frames.parquet and clips.parquet byte-identical; run.json equal except VOLATILE_FIELDS."""
    for f in ("frames.parquet", "clips.parquet"):
        assert (a / f).read_bytes() == (b / f).read_bytes(), f
    ma, mb = (json.loads((d / "run.json").read_text()) for d in (a, b))
    assert set(ma) == set(mb)
    assert {k: v for k, v in ma.items() if k not in VOLATILE_FIELDS} == \
           {k: v for k, v in mb.items() if k not in VOLATILE_FIELDS}


@pytest.fixture(scope="module")
def single(synth_probes, tmp_path_factory) -> Path:
    tmp = tmp_path_factory.mktemp("single")
    res = _voe("score", "--probes", str(synth_probes), "--model", MODEL, "--batch-size", "3", "--out",
               str(tmp / "run"), tmp=tmp)
    assert res.returncode == 0, res.stderr
    return tmp / "run"


def test_two_gloo_ranks_are_byte_identical_to_one_process(single, synth_probes, tmp_path):
    pytest.importorskip("torch.distributed")
    res = _voe("--standalone", "--nproc_per_node", "2", "-m", "voe", "score", "--probes", str(synth_probes),
               "--model", MODEL, "--batch-size", "3", "--out", str(tmp_path / "run"), tmp=tmp_path,
               runner=("-m", "torch.distributed.run"))
    assert res.returncode == 0, res.stderr
    _same_run(single, tmp_path / "run")
    meta = json.loads((tmp_path / "run" / "run.json").read_text())
    assert meta["launcher"] == {"name": "torchrun", "world_size": 2} and meta["clips_from_cache"] == 0
    assert not any((tmp_path / "xdg" / "voe" / "score").iterdir())  # the cache entry is gone once written


@pytest.mark.slow  # the same launch as above, through `voe score --launcher torchrun`
def test_launcher_option_execs_torchrun(single, synth_probes, tmp_path):
    pytest.importorskip("torch.distributed")
    res = _voe("score", "--probes", str(synth_probes), "--model", MODEL, "--batch-size", "3", "--out",
               str(tmp_path / "run"), "--launcher", "torchrun", "--nproc", "2", tmp=tmp_path)
    assert res.returncode == 0, res.stderr
    assert "torch.distributed.run" in res.stderr
    _same_run(single, tmp_path / "run")


def test_shards_are_whole_sets_without_duplicates(synth_probes):
    ps = load_probe_set(synth_probes)
    sched = plan(ps.index, 3)
    set_of = dict(zip(ps.index["clip_id"], ps.index["set_id"], strict=True))
    sets = [{set_of[c] for i in sched.for_rank(r, 2) for c in sched.batches[i]} for r in range(2)]
    clips = [[c for i in sched.for_rank(r, 2) for c in sched.batches[i]] for r in range(2)]
    assert not sets[0] & sets[1] and sets[0] and sets[1]
    assert sorted(clips[0] + clips[1]) == sorted(ps.index["clip_id"])  # each clip once, no padding


def test_job_array_shards_then_merge(single, synth_probes, tmp_path):
    """Three array tasks (`--shard i/3`) fill the cache; a final run merges without computing."""
    from voe.scoring.distributed import Ranks

    cache = tmp_path / "cache"
    for i in range(3):
        assert score_probe_set(RandomModel(), synth_probes, tmp_path / "run", batch_size=3, check=True,
                               cache_root=cache, ranks=Ranks(i, 3, "shard")) is None
        assert not (tmp_path / "run").exists()
    meta = score_probe_set(RandomModel(), synth_probes, tmp_path / "run", batch_size=3, check=True,
                           cache_root=cache, model_ref=MODEL)
    assert meta["clips_from_cache"] == 36
    _same_run(single, tmp_path / "run")
    res = _voe("score", "--probes", str(synth_probes), "--model", MODEL, "--out", str(tmp_path / "r2"),
               "--shard", "3/3", tmp=tmp_path)
    assert res.returncode == 1 and "--shard must be I/N with 0 <= I < N" in res.stderr


def test_failing_model_is_named_and_the_rerun_resumes(single, synth_probes, tmp_path):
    ps = load_probe_set(synth_probes)
    last = plan(ps.index, 3).batches[-2][0]  # late in the order, after most batches are cached
    key = clip_key(ps.manifest_sha256, last)
    args = ["score", "--probes", str(synth_probes), "--model", "tests.scoring.flaky:FlakyModel",
            "--model-arg", f"fail_key={key}", "--model-arg", f"marker={tmp_path / 'failed'}",
            "--model-arg", f"count={tmp_path / 'count'}", "--batch-size", "3", "--out", str(tmp_path / "run")]
    res = _voe(*args, tmp=tmp_path)
    lines = res.stderr.strip().splitlines()  # a progress line, then the error in one line
    assert res.returncode == 2 and lines[0].startswith("scoring flaky: 36 clips, check passed, cache under")
    assert len(lines) == 2 and lines[1].startswith("voe: error: "), res.stderr
    assert f"model 'flaky' raised RuntimeError on clip {key} (clip {last})" in lines[1]
    assert "simulated device fault with a second line" in lines[1] and "rerun the same command to resume" in lines[1]
    assert not (tmp_path / "run").exists()
    before = sum(int(n) for n in (tmp_path / "count").read_text().split())
    (tmp_path / "count").unlink()
    res = _voe(*args, tmp=tmp_path)
    assert res.returncode == 0, res.stderr
    again = sum(int(n) for n in (tmp_path / "count").read_text().split())
    meta = json.loads((tmp_path / "run" / "run.json").read_text())
    n_check = 7 * 6  # check_model scores its 6-clip sample 7 times (halves count once), in both runs
    assert meta["clips_from_cache"] == before - n_check and again - n_check == 36 - meta["clips_from_cache"] > 0
    for f in ("frames.parquet", "clips.parquet"):  # the same numbers as an uninterrupted run
        assert (tmp_path / "run" / f).read_bytes() == (single / f).read_bytes()


def test_killed_run_resumes_with_the_same_bytes(single, synth_probes, tmp_path):
    """SIGKILL partway (no clean-up at all), rerun: fewer clips computed, the same files."""
    import signal
    import time

    argv = ["score", "--probes", str(synth_probes), "--model", "tests.scoring.flaky:SlowModel", "--batch-size",
            "3", "--out", str(tmp_path / "run"), "--model-arg", "delay=0.1", "--cache", str(tmp_path / "c")]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    p = subprocess.Popen([sys.executable, "-m", "voe", *argv], cwd=ROOT, env=env, stderr=subprocess.DEVNULL)
    t0 = time.monotonic()
    while len(list(tmp_path.glob("c/*/batch-*.npz"))) < 4:
        assert p.poll() is None and time.monotonic() - t0 < 60
        time.sleep(0.05)
    p.send_signal(signal.SIGKILL)
    p.wait()
    assert not (tmp_path / "run").exists()
    res = _voe(*argv, tmp=tmp_path)
    assert res.returncode == 0, res.stderr
    meta = json.loads((tmp_path / "run" / "run.json").read_text())
    assert 12 <= meta["clips_from_cache"] < 36
    for f in ("frames.parquet", "clips.parquet"):
        assert (tmp_path / "run" / f).read_bytes() == (single / f).read_bytes()
    assert not list(tmp_path.glob("c/*/batch-*"))  # entry removed once the run is written


def test_python_api_failure_without_cache_says_so(synth_probes, tmp_path):
    from tests.scoring.flaky import FlakyModel

    ps = load_probe_set(synth_probes)
    key = clip_key(ps.manifest_sha256, plan(ps.index, 4).batches[0][0])
    with pytest.raises(ModelContractError, match="rerun with a cache"):
        score_probe_set(FlakyModel(key, str(tmp_path / "m")), synth_probes, tmp_path / "run", batch_size=4)


def test_device_and_bf16(synth_probes, tmp_path):
    pytest.importorskip("torch")
    from voe.models.loading import load_model

    model = load_model("mlp", {"n_slots": 2})
    meta = score_probe_set(model, synth_probes, tmp_path / "f32", device="cpu")
    assert meta["device"] == "cpu" and meta["bf16"] is False and model.device == "cpu"
    meta = score_probe_set(load_model("mlp", {"n_slots": 2}), synth_probes, tmp_path / "bf16", device="cpu", bf16=True)
    assert meta["bf16"] is True

    class Spy(RandomModel):
        seen: list = []

        def frame_nll(self, batch):
            import torch

            self.seen.append((torch.is_autocast_enabled("cpu"), torch.get_autocast_dtype("cpu")))
            return super().frame_nll(batch)

    import torch

    score_probe_set(Spy(), synth_probes, tmp_path / "spy", bf16=True)
    assert Spy.seen and all(s == (True, torch.bfloat16) for s in Spy.seen)
    with pytest.raises(VoeError, match="has no to\\(device\\) method"):
        score_probe_set(BlindModel(), synth_probes, tmp_path / "cuda", device="cuda")
    score_probe_set(RandomModel(), synth_probes, tmp_path / "numpy-cpu", device="cpu")  # cpu: nothing to move
