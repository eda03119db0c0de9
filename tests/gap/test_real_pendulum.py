"""The real single pendulum: the finder must name and fit the missing bearing damping."""

from __future__ import annotations

from pathlib import Path

import pytest

from voe.gap import GapFinder

DATA = Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "real" / "single-pendulum"


@pytest.mark.skipif(not (DATA / "recordings.csv").exists(), reason=f"real pendulum data not found at {DATA}")
def test_real_pendulum_damping_found():
    f = GapFinder(seed=0).fit(DATA / "scene.json", DATA / "recordings.csv")
    assert f.verdict_ == "mismatch"
    assert f.effects_[0]["name"] == "angular_damping"
    b = f.effects_[0]["params"]["b"]
    assert 1.2e-4 < b < 2.4e-4  # README: 1.76e-4 (exact ODE), authors 2.24e-4
    assert f.fit_["holdout_episodes"] == [4, 5]
    assert f.fit_["after"] < 0.7 * f.fit_["before"]
    assert f.located_ and all(x["context"] == "swinging" for x in f.located_)
