"""Shared fixtures: a tiny probe set generated once per session."""

from __future__ import annotations

from pathlib import Path

import pytest

from voe.concepts.generate import generate_probe_set
from voe.sim.scene import SimConfig

TINY = SimConfig(n_frames=40, size=32)


@pytest.fixture(scope="session")
def tiny_probes(tmp_path_factory) -> Path:
    """Two matched sets of every registered core concept, 32x32 frames."""
    from voe.concepts import CONCEPTS

    out = tmp_path_factory.mktemp("probes") / "set"
    generate_probe_set(out, CONCEPTS.ids(), 2, 0, TINY, jobs=1)
    return out
