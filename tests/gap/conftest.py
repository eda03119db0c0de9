"""Small synthetic scenes and recordings shared by the gap tests."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from voe.gap.effects import EFFECTS
from voe.gap.synth import simulate_episode
from voe.gap.truths import Gust
from voe.sim.scenefile import BodySpec, SceneSpec

BALL = {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "friction": 0.5, "elasticity": 0.5}


def flight_scene() -> SceneSpec:
    return SceneSpec((0.0, -9.81), (BodySpec("ball", "circle", mass=1.0, radius=0.1, friction=0.5, elasticity=0.5),))


def flight_episodes(effect: str = "none", params=(), n: int = 4, duration: float = 2.0, noise: float = 1e-3, seed: int = 0):
    """Balls thrown in free flight (no statics) with an optional hidden effect."""
    rng = np.random.default_rng(seed)
    scene = flight_scene()
    eff = EFFECTS.get(effect)()
    t = np.arange(int(duration * 100) + 1) / 100
    sigma = np.array([[noise, noise, 10 * noise]])
    eps = []
    for k in range(n):
        pose0 = np.array([[rng.uniform(-1, 1), rng.uniform(0, 1), 0.0]])
        vel0 = np.array([[rng.uniform(3, 5), rng.uniform(4, 7), rng.uniform(-5, 5)]])
        eps.append(simulate_episode(scene, k, t, pose0, vel0, eff, np.asarray(params, float), sigma, rng))
    return scene, eps


def gusty_episodes(gust: bool, n: int = 6, seed: int = 3):
    """``n`` episodes of a ball in flight pushed by a gust (``voe.gap.truths.Gust``) or by a constant
    acceleration of 0.5 m/s^2 along x; 3 s at 100 Hz."""
    rng = np.random.default_rng(seed)
    scene, t = flight_scene(), np.arange(301) / 100
    sigma = np.array([[1e-3, 1e-3, 1e-2]])
    ca = EFFECTS.get("constant_acceleration")()
    eps = []
    for k in range(n):
        pose0 = np.array([[rng.uniform(-1, 1), rng.uniform(0, 1), 0.0]])
        vel0 = np.array([[rng.uniform(1, 2), rng.uniform(8, 10), 0.0]])
        eff, p = (Gust(), np.array([1.0, 1.2, 0.3])) if gust else (ca, np.array([0.5, 0.0]))
        eps.append(simulate_episode(scene, k, t, pose0, vel0, eff, p, sigma, rng))
    return scene, eps


def to_table(scene: SceneSpec, eps) -> pd.DataFrame:
    rows = []
    for e in eps:
        for b, name in enumerate(scene.names):
            for k, t in enumerate(e.t):
                rows.append((e.id, round(float(t), 6), name, *e.pose[k, b]))
    return pd.DataFrame(rows, columns=["episode", "t", "body", "x", "y", "angle"])


@pytest.fixture
def flight_files(tmp_path: Path) -> tuple[Path, Path]:
    scene, eps = flight_episodes(n=3, duration=1.5)
    sp = tmp_path / "scene.json"
    sp.write_text(json.dumps({"units": {"length": "m"}, "gravity": [0, -9.81], "bodies": [BALL], "statics": [], "joints": []}))
    rp = tmp_path / "rec.csv"
    to_table(scene, eps).to_csv(rp, index=False)
    return sp, rp


@pytest.fixture
def no_stand_ins(monkeypatch):
    """Every later round's member counts as moving its windows (``voe.gap.stand_in``): for the
    search tests whose made-up fitters have selection errors but no predictions to move."""
    from voe.gap import search

    monkeypatch.setattr(search, "own_moved", lambda fitter, res, cand: float("inf"))
