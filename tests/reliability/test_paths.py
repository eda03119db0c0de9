"""Paths read from manifests, runs, checkpoint configs and controls files stay inside their folder."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from voe.errors import CheckpointError, ProbeSetError, RunError, VoeError
from voe.io.paths import inside, relative_ref, resolve_ref
from voe.io.probeset import load_probe_set
from voe.io.provenance import sha256_file

from .cli import assert_one_line_error, run_voe


def _copy(src: Path, tmp_path: Path) -> Path:
    dst = tmp_path / "set"
    shutil.copytree(src, dst)
    return dst


def _escape(tmp_path: Path) -> tuple[str, Path]:
    """A real file outside the set, named by a ``../`` path that reaches it from the set."""
    target = tmp_path / "outside" / "hostname"
    target.parent.mkdir()
    target.write_text("secret-host\n")
    return "../outside/hostname", target


def test_manifest_entry_outside_is_refused_by_validate_and_loading(tiny_probes, tmp_path):
    ps_dir = _copy(tiny_probes, tmp_path)
    name, target = _escape(tmp_path)
    m = json.loads((ps_dir / "manifest.json").read_text())
    m["files"][name] = sha256_file(target)
    (ps_dir / "manifest.json").write_text(json.dumps(m))
    with pytest.raises(ProbeSetError, match=r"'\.\./outside/hostname' leads outside"):
        load_probe_set(ps_dir)
    proc = run_voe("probes", "validate", ps_dir)
    assert_one_line_error(proc, "../outside/hostname", "leads outside")


def test_etc_hostname_entry_is_refused(tiny_probes, tmp_path):
    """The issue's case: ``../../../etc/hostname`` with that file's sha256."""
    host = Path("/etc/hostname")
    if not host.exists():
        pytest.skip("no /etc/hostname on this machine")
    ps_dir = _copy(tiny_probes, tmp_path)
    m = json.loads((ps_dir / "manifest.json").read_text())
    m["files"]["../" * len(ps_dir.resolve().parts) + "etc/hostname"] = sha256_file(host)
    (ps_dir / "manifest.json").write_text(json.dumps(m))
    assert_one_line_error(run_voe("probes", "validate", ps_dir), "etc/hostname", "leads outside")
    with pytest.raises(ProbeSetError, match="leads outside"):
        load_probe_set(ps_dir)


def test_symlinked_array_leading_outside_is_refused(tiny_probes, tmp_path):
    ps_dir = _copy(tiny_probes, tmp_path)
    outside = tmp_path / "frames-elsewhere.npy"
    frames = next(ps_dir.rglob("frames.npy"))
    shutil.move(frames, outside)
    frames.symlink_to(outside)
    with pytest.raises(ProbeSetError, match="frames.npy' leads outside"):
        load_probe_set(ps_dir)
    assert_one_line_error(run_voe("probes", "validate", ps_dir), "frames.npy", "leads outside")


def test_symlink_inside_is_fine(tmp_path):
    (tmp_path / "a.bin").write_bytes(b"x")
    (tmp_path / "b.bin").symlink_to(tmp_path / "a.bin")
    assert inside(tmp_path, "b.bin", "m.json") == tmp_path / "b.bin"
    for bad in ("/etc/passwd", "", None, 3, "a/../../x"):
        with pytest.raises(VoeError):
            inside(tmp_path, bad, "m.json")


def test_run_and_checkpoint_files_must_stay_inside(tmp_path):
    from voe.models.checkpoint import read_checkpoint, save_checkpoint
    from voe.scoring.runs import load_run

    run = tmp_path / "run"
    run.mkdir()
    (tmp_path / "elsewhere.json").write_text("{}")
    (run / "run.json").symlink_to(tmp_path / "elsewhere.json")
    with pytest.raises(RunError, match="leads outside"):
        load_run(run)
    ck = save_checkpoint(tmp_path / "ck", {"model": "constvel", "config": {}})
    (tmp_path / "cfg.json").write_text((ck / "config.json").read_text())
    (ck / "config.json").unlink()
    (ck / "config.json").symlink_to(tmp_path / "cfg.json")
    with pytest.raises(CheckpointError, match="leads outside"):
        read_checkpoint(ck)


def test_controls_checkpoint_outside_the_yaml_folder_is_refused(tmp_path):
    from voe.controls.spec import load_user_controls

    d = tmp_path / "ctl"
    d.mkdir()
    for ck, ok in (("../ckpt", False), ("/etc", False), ("ckpt/x", True)):
        (d / "c.yaml").write_text(f"controls:\n  - {{name: a, model: oracle, checkpoint: {ck}}}\n")
        if ok:
            assert load_user_controls(d / "c.yaml")[0].checkpoint == str(d / "ckpt/x")
        else:
            with pytest.raises(VoeError, match="c.yaml"):
                load_user_controls(d / "c.yaml")


def test_relative_refs_round_trip(tmp_path):
    (tmp_path / "probes").mkdir()
    ref = relative_ref(tmp_path / "probes", tmp_path / "runs" / "a")
    assert ref == "../../probes"
    assert resolve_ref(ref, tmp_path / "runs" / "a").resolve() == (tmp_path / "probes").resolve()
    assert resolve_ref("/abs/p", tmp_path) == Path("/abs/p")
