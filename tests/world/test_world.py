"""Training worlds: deterministic, stored like probe sets, counterfactuals do what they say."""

from __future__ import annotations

import json

import numpy as np
import pytest

from voe.errors import UnknownNameError
from voe.io.probeset import load_probe_set
from voe.sim.scene import SimConfig
from voe.world.generate import generate_world

CFG = SimConfig(n_frames=30, size=32)


def test_same_seed_is_byte_identical_whatever_jobs(tmp_path, monkeypatch):
    monkeypatch.setattr("voe.io.shards.MAX_SHARD_CLIPS", 2)  # several shards from 6 clips
    generate_world(tmp_path / "a", 6, 3, CFG, jobs=1)
    generate_world(tmp_path / "b", 6, 3, CFG, jobs=2)
    files = sorted(p.relative_to(tmp_path / "a") for p in (tmp_path / "a").rglob("*") if p.is_file())
    assert [p.relative_to(tmp_path / "b") for p in sorted((tmp_path / "b").rglob("*")) if p.is_file()] == files
    assert len(files) == 2 + 4 * 3  # manifest, index and 3 shards of 4 arrays
    for f in files:
        assert (tmp_path / "a" / f).read_bytes() == (tmp_path / "b" / f).read_bytes(), f
    generate_world(tmp_path / "c", 6, 4, CFG)
    st = "shards/00000/states.npy"
    assert (tmp_path / "a" / st).read_bytes() != (tmp_path / "c" / st).read_bytes()


def test_stored_as_training_set(tmp_path):
    generate_world(tmp_path / "w", 5, 0, CFG)
    ps = load_probe_set(tmp_path / "w")
    assert ps.manifest["kind"] == "train" and ps.manifest["counterfactual"] == "none"
    assert set(ps.index.role) == {"train"} and set(ps.index.set_kind) == {"train"}
    assert (ps.index.onset_frame == -1).all()
    assert ps.array("states").shape == (5, 30, 4, 11) and ps.array("frames").shape == (5, 30, 32, 32)
    assert ps.array("present").any()


@pytest.fixture(scope="module")
def worlds(tmp_path_factory):
    root = tmp_path_factory.mktemp("cf")
    out = {}
    for cf in ("none", "gravity_off", "pass_through", "vanish_when_occluded"):
        generate_world(root / cf, 24, 1, CFG, counterfactual=cf)
        out[cf] = load_probe_set(root / cf)
    return out


def test_counterfactuals_share_scenes_and_are_recorded(worlds):
    for cf, ps in worlds.items():
        assert ps.manifest["counterfactual"] == cf
        assert all(json.loads(p)["counterfactual"] == cf for p in ps.index.params)
    # same scenes: frame 0 is identical in every world
    np.testing.assert_array_equal(worlds["none"].array("states")[:, 0], worlds["pass_through"].array("states")[:, 0])


def test_gravity_off_objects_keep_vertical_velocity_in_flight(worlds):
    ps = worlds["gravity_off"]
    assert all(json.loads(g)["gravity"] == [0.0, 0.0] for g in ps.index.geometry)
    st = ps.array("states")
    vy = st[..., 4]
    dvy = np.abs(np.diff(vy, axis=1))
    assert np.nanmedian(dvy) < 1e-6  # no gravity: velocity only changes at contacts
    free_fall = 9.81 * CFG.dt  # |dvy| of one frame of free fall
    n_fall = np.sum(np.abs(np.abs(np.diff(worlds["none"].array("states")[..., 4], axis=1)) - free_fall) < 1e-3)
    assert n_fall > 20 and np.sum(np.abs(dvy - free_fall) < 1e-3) < n_fall / 10


def test_vanished_objects_never_return(worlds):
    ex = worlds["vanish_when_occluded"].array("exists")  # (N, T, K)
    came_back = (~ex[:, :-1] & ex[:, 1:]).any()
    assert not came_back
    ex0 = worlds["none"].array("exists")
    assert ex.sum() < ex0.sum()  # some object did hide behind a screen and vanish


def _deep_overlaps(ps) -> int:
    st = ps.array("states")
    x, y, w = st[..., 0], st[..., 1], st[..., 8]
    d = np.hypot(x[..., :, None] - x[..., None, :], y[..., :, None] - y[..., None, :])  # (N, T, K, K)
    r = (w[..., :, None] + w[..., None, :]) / 2
    return int(((d < 0.5 * r) & ~np.eye(st.shape[2], dtype=bool)).sum())


def test_pass_through_objects_overlap(worlds):
    assert _deep_overlaps(worlds["none"]) == 0  # solid objects never sink halfway into each other
    assert _deep_overlaps(worlds["pass_through"]) > 0


def test_unknown_counterfactual(tmp_path):
    with pytest.raises(UnknownNameError, match="did you mean 'gravity_off'"):
        generate_world(tmp_path / "x", 2, 0, CFG, counterfactual="gravity-off")


def test_cli_generates_and_rejects_bad_counterfactual(tmp_path):
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    run = [sys.executable, "-m", "voe", "world", "generate", "--n", "2", "--size", "32", "--frames", "12"]
    r = subprocess.run([*run, "--out", str(tmp_path / "w"), "--counterfactual", "pass_through"],
                       cwd=root, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert load_probe_set(tmp_path / "w").manifest["counterfactual"] == "pass_through"
    r = subprocess.run([*run, "--out", str(tmp_path / "x"), "--counterfactual", "no_gravity"],
                       cwd=root, capture_output=True, text=True, timeout=120)
    assert r.returncode == 1 and r.stderr.strip().startswith("voe: error: unknown counterfactual")
