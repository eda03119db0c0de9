"""SIGINT or SIGTERM partway through a long command leaves nothing that looks complete, and a rerun works.

Each test starts ``python -m voe ...`` as a user would, waits until it shows progress, interrupts
it, checks that no final-named output exists (only a complete output may carry its final name),
that no temporary sibling or lock is left, and reruns the command (smaller where the first run
was sized to be interrupted) to completion.
"""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from voe.scoring.runs import load_run

from ..gap.conftest import BALL, flight_episodes, to_table
from .cli import env, run_voe

SWALLOWED = "arrived where it could not stop the command"


def interrupt(args: list[object], tmp_path: Path, sig: int, after: str, delay: float = 0.5,
              timeout: float = 120, outputs: tuple[Path, ...] = (), whole: str = "manifest.json",
              reset: tuple[Path, ...] = (), **extra: str) -> subprocess.CompletedProcess:
    """Run the CLI, send ``sig`` ``delay`` s after ``after`` appears in its output, wait for it to end.

    A signal can land where Python swallows what its handler raises (C code that clears errors
    after calling back into Python); the command then runs to its end and says so in one line,
    with exit 130 and complete outputs (``voe.cli.main._swallowed``). That documented fallback is
    accepted only for commands whose ``outputs`` are given: each must then be whole (it holds
    the file ``whole``, which the command writes last), is removed together with the stages it
    cached (``reset``, so that the rerun passes ``after`` again), and the command is interrupted
    again. At least one of three attempts must really stop it, so a command that can never be
    interrupted still fails here.
    """
    for attempt in range(3):
        run = _interrupt_once(args, tmp_path, sig, after, delay, timeout, **extra)
        if SWALLOWED not in run.stdout or not outputs:
            break
        print(f"attempt {attempt + 1}: the signal was swallowed and the command ran to its end")
        for out in outputs:
            assert (out / whole).exists(), f"a command that ran to its end left {out} incomplete"
            shutil.rmtree(out)
        for cached in reset:
            shutil.rmtree(cached, ignore_errors=True)
    assert "voe: interrupted" in run.stdout, run.stdout
    return run


def _interrupt_once(args: list[object], tmp_path: Path, sig: int, after: str, delay: float, timeout: float,
                    **extra: str) -> subprocess.CompletedProcess:
    """One run of :func:`interrupt`: started, signalled, ended non-zero without a traceback."""
    log = tmp_path / f"log-{time.monotonic_ns()}.txt"
    with open(log, "w") as fh:
        # as from a terminal: SIGINT is not ignored (background jobs of a script inherit SIG_IGN)
        p = subprocess.Popen([sys.executable, "-m", "voe", *map(str, args)], stdout=fh, stderr=subprocess.STDOUT,
                             env=env(**extra), text=True,
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # noqa: PLW1509
        t0 = time.monotonic()
        while after not in log.read_text():
            assert p.poll() is None, f"ended before '{after}': {log.read_text()}"
            assert time.monotonic() - t0 < timeout, log.read_text()
            time.sleep(0.05)
        time.sleep(delay)
        assert p.poll() is None, f"finished before it could be interrupted: {log.read_text()}"
        p.send_signal(sig)
        t1 = time.monotonic()
        code = p.wait(timeout=60)
    out = log.read_text()
    print(f"interrupted after {time.monotonic() - t0:.1f} s, ended {time.monotonic() - t1:.1f} s after the signal")
    assert code != 0, out
    assert "Traceback" not in out, out
    return subprocess.CompletedProcess(args, code, out, "")


def assert_nothing_left(out: Path) -> None:
    """No final-named output, no temporary sibling, no lock."""
    assert not out.exists(), sorted(p.name for p in out.iterdir())
    if not out.parent.exists():
        return
    left = [p.name for p in out.parent.iterdir() if p.name.startswith(f".{out.name}.")]
    assert left == [], left


def test_probes_generate(tmp_path):
    out = tmp_path / "p"
    interrupt(["probes", "generate", "--out", out, "--per-concept", "30", "--size", "32"], tmp_path,
              signal.SIGINT, "matched sets", outputs=(out,))
    assert_nothing_left(out)
    proc = run_voe("probes", "generate", "--out", out, "--per-concept", "1", "--size", "32")
    assert proc.returncode == 0, proc.stderr
    assert (out / "manifest.json").exists()


def test_world_generate(tmp_path):
    out = tmp_path / "w"
    interrupt(["world", "generate", "--out", out, "--n", "2000", "--size", "32"], tmp_path,
              signal.SIGTERM, "training clips", outputs=(out,))
    assert_nothing_left(out)
    proc = run_voe("world", "generate", "--out", out, "--n", "4", "--size", "32")
    assert proc.returncode == 0 and (out / "manifest.json").exists(), proc.stderr


def test_score(tiny_probes, tmp_path):
    out = tmp_path / "run"
    model = "tests.reliability.slow_model:Slow"
    interrupt(["score", "--probes", tiny_probes, "--model", model, "--model-arg", "delay=0.3",
               "--batch-size", "2", "--out", out], tmp_path, signal.SIGTERM, "scoring", delay=1.5,
              XDG_CACHE_HOME=str(tmp_path / "cache"))
    assert_nothing_left(out)
    proc = run_voe("score", "--probes", tiny_probes, "--model", model, "--batch-size", "2", "--out", out,
                   XDG_CACHE_HOME=str(tmp_path / "cache"))
    assert proc.returncode == 0, proc.stderr
    from voe.io.probeset import load_probe_set

    assert len(load_run(out).clips) == len(load_probe_set(tiny_probes))


def test_gap(tmp_path):
    spec, eps = flight_episodes(n=3, duration=1.5)
    scene, rec = tmp_path / "scene.json", tmp_path / "rec.csv"
    scene.write_text(json.dumps({"gravity": [0, -9.81], "bodies": [BALL]}))
    to_table(spec, eps).to_csv(rec, index=False)
    out = tmp_path / "g"
    interrupt(["gap", scene, rec, "--out", out, "--jobs", "1"], tmp_path, signal.SIGINT, "voe gap", delay=0.3)
    assert_nothing_left(out)
    proc = run_voe("gap", scene, rec, "--out", out, "--effects", "linear_drag", "--no-figures", "--jobs", "1")
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "gap.json").read_text())["verdict"] in ("mismatch", "consistent")


def test_validate_suite_scratch_in_the_user_cache(tmp_path):
    out, cache = tmp_path / "v", tmp_path / "cache"
    args = ["validate-suite", "--out", out, "--per-concept", "2", "--world-n", "10", "--family", "knowledge-free"]
    # the report directory appears whole or not at all (renamed from a temporary sibling), its
    # provenance written with it; seen once in CI: the documented fallback (SIGTERM swallowed)
    run = interrupt(args, tmp_path, signal.SIGTERM, "probe sets", delay=0.3, outputs=(out,),
                    whole="provenance.json", reset=(cache,), XDG_CACHE_HOME=str(cache))
    from voe.io.outputs import code_fingerprint

    name = f"validity-2x10-seed0-{code_fingerprint()}"
    scratch = cache / "voe" / name
    assert f"scratch directory (reused on rerun): {scratch}" in run.stdout
    assert_nothing_left(out)
    probes = scratch / "probes"
    if probes.exists():  # the stage may finish before the signal lands: then it must be whole
        check = run_voe("probes", "validate", probes)
        assert check.returncode == 0, check.stdout + check.stderr
        assert [p.name for p in scratch.iterdir() if p.name.startswith(".probes.")] == []
    else:
        assert_nothing_left(probes)
    proc = run_voe(*args, XDG_CACHE_HOME=str(cache), cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (out / "matrix.csv").exists() and (scratch / "probes" / "manifest.json").exists()
    assert not (tmp_path / "voe-work").exists()
    prov = json.loads((out / "provenance.json").read_text())      # portable: no absolute path
    assert prov["probes"] == f"../cache/voe/{name}/probes" and len(prov["probes_manifest_sha256"]) == 64
    assert str(tmp_path) not in (out / "validity.md").read_text() + (out / "provenance.json").read_text()


@pytest.mark.slow
def test_train(tmp_path):
    """A checkpoint appears only when complete (slow: torch start-up and a world, ~30 s)."""
    world, ck = tmp_path / "w", tmp_path / "ck"
    assert run_voe("world", "generate", "--out", world, "--n", "30", "--size", "32").returncode == 0
    interrupt(["train", "interaction", "--data", world, "--out", ck, "--steps", "100000"], tmp_path,
              signal.SIGTERM, "train interaction", delay=2.0)
    assert_nothing_left(ck)
    proc = run_voe("train", "interaction", "--data", world, "--out", ck, "--steps", "3")
    assert proc.returncode == 0 and (ck / "config.json").exists(), proc.stderr


@pytest.mark.slow
def test_demo(tmp_path):
    """The quick demo interrupted while training (slow: ~2 min): completed stages are kept, nothing
    incomplete carries a final name, and the rerun finishes."""
    out, work = tmp_path / "demo", tmp_path / "work"
    args = ["demo", "--quick", "--no-validity", "--out", out, "--work", work]
    interrupt(args, tmp_path, signal.SIGINT, "training 3 model", delay=3.0)
    assert_nothing_left(out)
    assert (work / "probes" / "manifest.json").exists()            # complete stages are kept ...
    for ck in (work / "checkpoints").glob("[!.]*"):                # ... and whatever has a final name
        assert (ck / "config.json").exists() and (ck / "weights.safetensors").exists(), ck  # is complete
    proc = run_voe(*args, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert (out / "report.md").exists()
