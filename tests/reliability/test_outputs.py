"""Output paths are checked before any work, locked against a second writer, and honour the umask."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from voe.cli.main import app
from voe.errors import VoeError
from voe.io.atomic import atomic_dir, atomic_write_bytes, umask
from voe.io.lock import OutputLockedError, lock_path, output_lock
from voe.io.outputs import claim_output, code_fingerprint, scratch_dir

from .cli import assert_one_line_error, env, run_voe


def _refused(args: list[str], *needles: str) -> str:
    """In-process run of the CLI: the command raised a one-line VoeError (what main() prints)."""
    res = CliRunner().invoke(app, [str(a) for a in args])
    assert isinstance(res.exception, VoeError), (res.output, res.exception)
    msg = str(res.exception)
    assert "\n" not in msg
    for n in needles:
        assert n in msg, msg
    return msg


@pytest.fixture
def afile(tmp_path) -> Path:
    p = tmp_path / "afile"
    p.write_text("x")
    return p


@pytest.fixture
def full(tmp_path) -> Path:
    d = tmp_path / "full"
    d.mkdir()
    (d / "keep.txt").write_text("precious")
    return d


def test_probes_generate_into_a_file_is_one_line(afile):
    proc = run_voe("probes", "generate", "--out", afile, "--per-concept", "1")
    assert_one_line_error(proc, str(afile), "is a file")


def test_nonempty_directory_is_refused_before_generating(full):
    t0 = time.monotonic()
    proc = run_voe("probes", "generate", "--out", full, "--per-concept", "50")
    assert_one_line_error(proc, str(full), "not empty", "--overwrite")
    assert "matched sets" not in proc.stderr          # no progress bar: nothing was generated
    assert time.monotonic() - t0 < 30
    assert (full / "keep.txt").read_text() == "precious"


def test_every_command_checks_its_output_first(tmp_path, afile, full, tiny_probes):
    png = tmp_path / "old.png"
    png.write_bytes(b"png")
    cases = [
        (["world", "generate", "--n", "5", "--out", afile], "is a file"),
        (["world", "generate", "--n", "5", "--out", full], "not empty"),
        (["train", "constvel", "--data", tiny_probes, "--out", afile], "is a file"),
        (["train", "constvel", "--data", tiny_probes, "--out", full], "not empty"),
        (["train", "constvel", "--data", tmp_path / "nope", "--out", tmp_path / "ck"], "does not exist"),
        (["train", "constvell", "--data", tiny_probes, "--out", tmp_path / "ck"], "constvell"),
        (["score", "--probes", tiny_probes, "--model", "constvel", "--out", afile], "is a file"),
        (["score", "--probes", tiny_probes, "--model", "constvel", "--out", full], "not empty"),
        (["report", str(tmp_path), "--out", afile], "is a file"),
        (["validate-suite", "--out", afile], "is a file"),
        (["validate-suite", "--out", full], "not empty"),
        (["validate-suite", "--out", tmp_path / "v", "--probes", tmp_path / "nope"], "does not exist"),
        (["demo", "--out", afile], "is a file"),
        (["demo", "--out", full], "not empty"),
        (["gap", afile, afile, "--out", afile], "is a file"),
        (["gap", afile, afile, "--out", full], "not empty"),
        (["probes", "show", tiny_probes, "--set", "x", "--out", png], "already exists"),
        (["probes", "show", tiny_probes, "--set", "x", "--out", full], "is a directory"),
        (["probes", "show", tiny_probes, "--set", "x", "--out", tmp_path / "a.jpg"], ".png, .svg, .gif"),
        (["probes", "generate", "--out", afile / "sub"], "is a file, so nothing can be created"),
    ]
    for args, needle in cases:
        _refused(args, needle)
    assert (full / "keep.txt").read_text() == "precious" and afile.read_text() == "x"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "full", "old.png"]   # nothing was created


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write anywhere")
def test_unwritable_parent_is_refused(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir(mode=0o555)
    _refused(["world", "generate", "--n", "5", "--out", ro / "w"], "not writable")


def test_commands_rerun_in_place_replace_only_their_own_output(tmp_path):
    """A report-like default output that holds an earlier result is replaced; others are not."""
    d = tmp_path / "rep"
    d.mkdir()
    (d / "report.md").write_text("old")
    with claim_output(d, "dir", replaces=("report.md",)):
        pass
    (d / "report.md").unlink()
    (d / "other").write_text("x")
    with pytest.raises(VoeError, match="not empty"), claim_output(d, "dir", replaces=("report.md",)):
        pass


@pytest.mark.parametrize("mask", [0o022, 0o077, 0o002])
def test_atomic_outputs_honour_the_umask(tmp_path, mask):
    old = os.umask(mask)
    try:
        with atomic_dir(tmp_path / "d") as tmp:
            (tmp / "f.bin").write_bytes(b"1")
            (tmp / "sub").mkdir()
        atomic_write_bytes(tmp_path / "set.gif", b"GIF89a")
        (tmp_path / "direct").mkdir()
        (tmp_path / "direct.bin").write_bytes(b"1")
    finally:
        os.umask(old)
    mode = lambda p: p.stat().st_mode & 0o777  # noqa: E731
    assert mode(tmp_path / "d") == mode(tmp_path / "direct") == 0o777 & ~mask
    assert mode(tmp_path / "d" / "sub") == 0o777 & ~mask
    assert mode(tmp_path / "set.gif") == mode(tmp_path / "direct.bin") == 0o666 & ~mask
    assert mode(tmp_path / "d" / "f.bin") == 0o666 & ~mask


def test_probe_set_and_filmstrip_follow_the_umask(tiny_probes, tmp_path):
    proc = subprocess.run(["sh", "-c", 'umask 022 && exec "$0" -m voe "$@"', sys.executable, "probes", "show",
                           str(tiny_probes), "--set", "permanence-0000", "--out", str(tmp_path / "s.gif")],
                          env=env(), capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "s.gif").stat().st_mode & 0o777 == 0o644
    assert tiny_probes.stat().st_mode & 0o777 == 0o777 & ~umask()


def _holder(path: Path) -> subprocess.Popen:
    code = ("import sys, time; from voe.io.lock import output_lock\n"
            f"with output_lock({str(path)!r}):\n    print('held', flush=True); time.sleep(60)\n")
    p = subprocess.Popen([sys.executable, "-c", code], env=env(), stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "held"
    return p


def test_second_writer_refuses_naming_the_first_and_a_dead_lock_is_taken_over(tmp_path):
    out = tmp_path / "w"
    first = _holder(out)
    try:
        proc = run_voe("world", "generate", "--n", "3", "--size", "32", "--out", out)
        assert_one_line_error(proc, f"being written by process {first.pid}", str(lock_path(out)))
        with pytest.raises(OutputLockedError, match=str(first.pid)), output_lock(out):
            pass
    finally:
        first.send_signal(signal.SIGKILL)
        first.wait()
    assert lock_path(out).exists()                      # a SIGKILLed writer leaves its lock behind
    proc = run_voe("world", "generate", "--n", "3", "--size", "32", "--out", out)
    assert proc.returncode == 0, proc.stderr             # ... which is stale and taken over
    assert (out / "manifest.json").exists() and not lock_path(out).exists()


def test_the_lock_is_reentrant_in_a_process(tmp_path):
    with output_lock(tmp_path / "x"), output_lock(tmp_path / "x"):
        assert int(lock_path(tmp_path / "x").read_text()) == os.getpid()
    assert not lock_path(tmp_path / "x").exists()


def test_scratch_goes_to_the_user_cache(monkeypatch, tmp_path):
    fp = code_fingerprint()
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    assert scratch_dir("validity") == tmp_path / "cache" / "voe" / f"validity-{fp}"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert scratch_dir("demo") == tmp_path / "home" / ".cache" / "voe" / f"demo-{fp}"


def test_scratch_of_other_code_is_not_reused(tmp_path):
    # a rerun after an upgrade once reported the previous version's stored runs as new
    src = tmp_path / "src"
    (src / "voe" / "models").mkdir(parents=True)
    (src / "probes" / "gravity").mkdir(parents=True)
    (src / "voe" / "models" / "m.py").write_text("A = 1\n")
    (src / "probes" / "gravity" / "spec.yaml").write_text("id: Gravity-v4\n")
    before = code_fingerprint(src)
    assert code_fingerprint(src) == before and len(before) == 12
    (src / "voe" / "models" / "m.py").write_text("A = 2\n")
    changed = code_fingerprint(src)
    assert changed != before
    (src / "probes" / "gravity" / "spec.yaml").write_text("id: Gravity-v5\n")
    assert code_fingerprint(src) not in (before, changed)
