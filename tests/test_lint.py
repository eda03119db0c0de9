"""The sources pass the linter the project declares (``[tool.ruff]`` in pyproject.toml).

Why a test: CI runs only the README's test command, so a lint rule the project selects (import
order, unused names, pyupgrade) was never enforced; session 34 landed an import out of order in
``voe/gap/check.py`` that only a manual ``ruff check`` showed."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_ruff_check_passes():
    pytest.importorskip("ruff", reason="ruff comes with the dev extra (pip install -e '.[dev]')")
    out = subprocess.run([sys.executable, "-m", "ruff", "check", "voe", "tests", "bench"], cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-1000:]
