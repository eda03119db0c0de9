"""Change points, context labels and atomic output."""

from __future__ import annotations

import numpy as np

from voe.gap.context import frame_labels, summarize
from voe.gap.locate import change_points
from voe.gap.output import atomic_write, provenance, sha256
from voe.gap.recordings import Episode
from voe.sim.scenefile import BodySpec, SceneSpec, StaticSpec


def test_change_point_finds_the_step():
    s = np.r_[np.zeros(10), np.full(6, 3.0)] + 0.01 * np.sin(np.arange(16))
    assert change_points(s, penalty=1.0) == [(0, 10), (10, 16)]
    assert change_points(np.zeros(8), penalty=1.0) == [(0, 8)]


def test_context_labels_flight_rolling_and_swinging():
    ball = BodySpec("ball", "circle", mass=1.0, radius=0.1)
    scene = SceneSpec((0.0, -9.81), (ball,), (StaticSpec((-5.0, 0.0), (5.0, 0.0)),))
    t = np.arange(50) / 100
    rolling = np.stack([t * 1.0, np.full_like(t, 0.1), -t * 1.0 / 0.1], axis=1)[:, None]  # v = -omega r
    labels = frame_labels(scene, Episode(0, t, rolling))[:, 0]
    assert summarize(labels[5:-5], rolling[5:-5, 0])[0] == "rolling"
    flying = np.stack([t, 1.0 + t - 4.9 * t**2, np.zeros_like(t)], axis=1)[:, None]
    assert summarize(frame_labels(scene, Episode(0, t, flying))[:, 0], flying[:, 0])[0] == "flight"
    sliding = np.stack([t * 1.0, np.full_like(t, 0.1), np.zeros_like(t)], axis=1)[:, None]
    assert summarize(frame_labels(scene, Episode(0, t, sliding))[5:-5, 0], sliding[5:-5, 0])[0] == "sliding"


def test_atomic_write_and_provenance(tmp_path):
    p = tmp_path / "sub" / "a.json"
    atomic_write(p, "hello")
    assert p.read_text() == "hello" and not list(p.parent.glob(".*tmp"))
    prov = provenance(7, {"scene": p})
    assert prov["seed"] == 7 and prov["inputs"]["scene"]["sha256"] == sha256(p)
    assert prov["inputs"]["scene"]["sha256"].startswith("2cf24dba")  # sha256("hello")
    assert prov["packages"]["pymunk"]
