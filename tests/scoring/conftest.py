"""A synthetic probe set (no simulator) and runs of the fake models, made once per session."""

from __future__ import annotations

from pathlib import Path

import pytest

from voe.scoring.score import score_probe_set
from voe.testing import BlindModel, CheatingModel, PixelSumModel, RandomModel

from .synth import make_probe_set

N_SETS = 6  # per concept; 2**-6 < 0.05/2, so a perfect model is "learned" even after Holm


@pytest.fixture(scope="session")
def synth_probes(tmp_path_factory) -> Path:
    return make_probe_set(tmp_path_factory.mktemp("scoring") / "probes", N_SETS)


@pytest.fixture(scope="session")
def fake_runs(synth_probes, tmp_path_factory) -> dict[str, Path]:
    """Run directories of the cheating, blind, random and pixel-sum models, by model name."""
    root = tmp_path_factory.mktemp("runs")
    out = {}
    for model in (CheatingModel(synth_probes), BlindModel(), RandomModel(), PixelSumModel()):
        out[model.name] = root / model.name
        score_probe_set(model, synth_probes, out[model.name], batch_size=5)
    return out
