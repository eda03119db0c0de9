"""Shared fixtures of the fuzz tests."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture(scope="module")
def scratch(tmp_path_factory) -> Path:
    """One scratch folder per module, reused by every drawn example."""
    return tmp_path_factory.mktemp("fuzz")
