import json
import shutil

import numpy as np
import pytest

from voe.concepts.generate import generate_probe_set
from voe.errors import ProbeSetError, VoeError
from voe.io.probeset import load_probe_set
from voe.io.validate import validate_probe_set
from voe.sim.scene import FEATURE_NAMES, SimConfig

CFG = SimConfig(size=32)


def test_same_seed_gives_byte_identical_sets_whatever_jobs(tmp_path):
    m1 = generate_probe_set(tmp_path / "a", ["Permanence-v2"], 3, 7, CFG, jobs=1)
    m2 = generate_probe_set(tmp_path / "b", ["Permanence-v2"], 3, 7, CFG, jobs=2)
    assert m1["files"] == m2["files"]
    assert (tmp_path / "a/manifest.json").read_bytes() == (tmp_path / "b/manifest.json").read_bytes()
    m3 = generate_probe_set(tmp_path / "c", ["Permanence-v2"], 3, 8, CFG)
    assert m3["files"]["shards/00000/frames.npy"] != m1["files"]["shards/00000/frames.npy"]


def test_load_round_trip_and_api(tiny_probes):
    ps = load_probe_set(tiny_probes)
    idx = ps.index
    for col in ("clip_id", "concept", "set_id", "variant", "role", "onset_frame", "seed",
                "visible_violation", "n_distractors", "params"):
        assert col in idx.columns
    json.loads(idx.params.iloc[0])
    ids = list(idx.clip_id[:3])
    data = ps.get(ids)
    T, S = ps.manifest["n_frames"], ps.manifest["frame_size"][0]
    assert data["frames"].shape == (3, T, S, S) and data["frames"].dtype == np.uint8
    assert data["states"].shape == (3, T, 4, len(FEATURE_NAMES))
    assert data["present"].dtype == bool
    batch = ps.batch(ids)
    assert batch.shape == (3, T) and batch.feature_names == FEATURE_NAMES
    assert "occluders" in batch.geometry[0]
    assert set(idx.role) == {"possible", "impossible"}


def test_validate_passes_then_catches_corruption(tiny_probes, tmp_path):
    assert validate_probe_set(load_probe_set(tiny_probes)).ok
    bad = tmp_path / "bad"
    shutil.copytree(tiny_probes, bad)
    arr = np.load(bad / "shards/00000/frames.npy")
    arr[2, 5, 0, 0] ^= 1
    np.save(bad / "shards/00000/frames.npy", arr)
    rep = validate_probe_set(load_probe_set(bad))
    assert any("sha256" in p for p in rep.problems)
    assert any("lacks F" in p or "frames differ" in p for p in rep.problems)


def test_bad_directories_give_clear_errors(tmp_path):
    with pytest.raises(ProbeSetError, match="does not exist"):
        load_probe_set(tmp_path / "nope")
    (tmp_path / "empty").mkdir()
    with pytest.raises(ProbeSetError, match="manifest.json is missing"):
        load_probe_set(tmp_path / "empty")
    (tmp_path / "empty/manifest.json").write_text("{not json")
    with pytest.raises(ProbeSetError, match="not valid JSON"):
        load_probe_set(tmp_path / "empty")


def test_refuses_to_overwrite_and_leaves_no_partial_output(tmp_path):
    out = tmp_path / "set"
    generate_probe_set(out, ["Permanence-v2"], 1, 0, CFG)
    before = (out / "manifest.json").read_bytes()
    with pytest.raises(VoeError, match="already exists"):
        generate_probe_set(out, ["Permanence-v2"], 1, 1, CFG)
    assert (out / "manifest.json").read_bytes() == before
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
