"""Fixtures: a tiny training world generated once per session."""

from __future__ import annotations

from pathlib import Path

import pytest

from voe.io.probeset import load_probe_set
from voe.sim.scene import SimConfig
from voe.world.generate import generate_world

SMALL = SimConfig(n_frames=20, size=32)


@pytest.fixture(scope="session")
def tiny_world(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("world") / "w"
    generate_world(out, 16, 7, SMALL)
    return out


@pytest.fixture(scope="session")
def tiny_batch(tiny_world):
    ps = load_probe_set(tiny_world)
    return ps.batch(list(ps.index.clip_id[:6]))
