"""The CLI: user models by reference, one-line errors and exit codes on bad input."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def voe(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "voe", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)


def test_user_model_checked_by_reference(tiny_world):
    r = voe("model", "check", "tests.models.user_model:Thing", "--model-arg", "scale=2", "--data", str(tiny_world))
    assert r.returncode == 0, r.stderr
    assert "ok" in r.stdout


@pytest.mark.parametrize("ref, code, msg", [
    ("tests.models.user_model:WrongShape", 2, "returned shape (20,), expected (B, T) = (6, 20)"),
    ("tests.models.user_model:NaNInside", 2, "NaN at clip 0, frame 5"),
    ("tests.models.user_model:Nothing", 1, "has no attribute 'Nothing'"),
    ("interactoin", 1, "did you mean 'interaction-v3'"),
])
def test_bad_models_exit_with_one_line(ref, code, msg, tiny_world):
    r = voe("model", "check", ref, "--data", str(tiny_world))
    assert r.returncode == code, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("voe: error:") and msg in lines[0], r.stderr


def test_bad_checkpoints_and_data(tmp_path, tiny_world):
    r = voe("model", "check", "mlp", "--checkpoint", str(tmp_path / "missing"), "--data", str(tiny_world))
    assert r.returncode == 1 and "does not exist" in r.stderr
    (tmp_path / "empty").mkdir()
    r = voe("train", "mlp", "--data", str(tmp_path / "empty"), "--out", str(tmp_path / "ck"), "--steps", "1")
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1 and "manifest.json" in r.stderr
    r = voe("train", "framecopy", "--data", str(tiny_world), "--out", str(tmp_path / "fc"))
    assert r.returncode == 0, r.stderr
    r = voe("model", "check", "pixel", "--checkpoint", str(tmp_path / "fc"), "--data", str(tiny_world))
    assert r.returncode == 1 and "not 'pixel-v1'" in r.stderr


def test_model_list():
    r = voe("model", "list")
    assert r.returncode == 0
    for name in ("framecopy-v1", "constvel-v1", "oracle-v1", "mlp-v2", "interaction-v2", "interaction-v3", "pixel-v1"):
        assert name in r.stdout
