"""Reuse the scoring fixtures: a synthetic probe set and runs of the fake models."""

from tests.scoring.conftest import N_SETS, fake_runs, synth_probes  # noqa: F401
