"""Sharded storage: reads across shard boundaries, legacy sets, refusals, bounded write memory."""

from __future__ import annotations

import json
import tracemalloc

import numpy as np
import pytest

from voe.errors import ProbeSetError
from voe.io.probeset import ClipRecord, load_probe_set, write_probe_set
from voe.io.shards import shard_clips

T, S, K, F = 6, 48, 2, 3
META = {"kind": "train", "dt": 0.05, "n_frames": T, "frame_size": [S, S], "n_slots": K,
        "feature_names": ["x", "y", "z"]}


def _records(n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    for i in range(n):
        row = {"clip_id": f"c{i:04d}", "concept": "train", "set_id": f"c{i:04d}", "variant": "train",
               "role": "train", "onset_frame": -1, "seed": i, "visible_violation": False,
               "n_distractors": 0, "params": "{}", "geometry": json.dumps({"i": i})}
        yield ClipRecord(row, rng.integers(0, 256, (T, S, S), dtype=np.uint8),
                         rng.normal(size=(T, K, F)).astype(np.float32),
                         rng.random((T, K)) < 0.5, np.ones((T, K), bool))


def test_shard_size_depends_on_clip_bytes_only():
    assert shard_clips(171_000) == 256  # 64 px, 40 frames
    assert shard_clips(2_100_000) == 31  # 224 px
    assert shard_clips(10**9) == 1


def test_reads_match_the_written_clips_across_shards(tmp_path, monkeypatch):
    monkeypatch.setattr("voe.io.shards.MAX_SHARD_CLIPS", 4)
    recs = list(_records(11))
    m = write_probe_set(tmp_path / "s", iter(recs), META)
    assert [s["n_clips"] for s in m["shards"]] == [4, 4, 3] and m["n_clips"] == 11
    assert sorted(m["files"]) == sorted(["index.parquet"] + [f"shards/{i:05d}/{a}.npy" for i in range(3)
                                                             for a in ("frames", "states", "present", "exists")])
    ps = load_probe_set(tmp_path / "s")
    frames = np.stack([r.frames for r in recs])  # (N, T, S, S)
    ids = ["c0009", "c0002", "c0005", "c0002", "c0010"]  # out of order, repeated, three shards
    rows = [9, 2, 5, 2, 10]
    got = ps.get(ids)
    np.testing.assert_array_equal(got["frames"], frames[rows])
    np.testing.assert_array_equal(got["states"], np.stack([r.states for r in recs])[rows])
    b = ps.batch(ids)
    assert b.clip_ids == tuple(ids) and [g["i"] for g in b.geometry] == rows
    arr = ps.array("frames")
    assert arr.shape == frames.shape and arr.dtype == np.uint8 and len(arr) == 11
    np.testing.assert_array_equal(arr[3:6], frames[3:6])
    np.testing.assert_array_equal(arr[7], frames[7])
    np.testing.assert_array_equal(arr[-1], frames[-1])
    np.testing.assert_array_equal(arr[:, 0], frames[:, 0])
    np.testing.assert_array_equal(arr[..., 1], frames[..., 1])
    np.testing.assert_array_equal(np.asarray(arr), frames)
    assert ps.array("present").any() == np.stack([r.present for r in recs]).any()
    assert [len(b) for b in ps.batches(list(ps.index.clip_id), size=4)] == [4, 4, 3]
    np.testing.assert_array_equal(ps.shard_of(np.array([0, 3, 4, 10])), [0, 0, 1, 2])


def test_legacy_single_array_sets_are_still_read(tmp_path):
    recs = list(_records(3))
    write_probe_set(tmp_path / "new", recs, META)
    old = tmp_path / "old"
    old.mkdir()
    (old / "index.parquet").write_bytes((tmp_path / "new/index.parquet").read_bytes())
    for a in ("frames", "states", "present", "exists"):
        np.save(old / f"{a}.npy", np.stack([getattr(r, a) for r in recs]))
    manifest = json.loads((tmp_path / "new/manifest.json").read_text())
    manifest.update(schema_version=1, files={})
    del manifest["shards"]
    (old / "manifest.json").write_text(json.dumps(manifest))
    ps = load_probe_set(old)
    assert ps.data_files() == ["frames.npy", "states.npy", "present.npy", "exists.npy"]
    np.testing.assert_array_equal(ps.get(["c0001"])["frames"][0], recs[1].frames)


def _tamper(path, **changes):
    m = json.loads((path / "manifest.json").read_text())
    m.update(changes)
    (path / "manifest.json").write_text(json.dumps(m))


def test_refusals_are_one_line(tmp_path):
    write_probe_set(tmp_path / "s", _records(3), META)
    _tamper(tmp_path / "s", schema_version=9)
    with pytest.raises(ProbeSetError, match="schema_version 9 is not one of"):
        load_probe_set(tmp_path / "s")
    _tamper(tmp_path / "s", schema_version=2, shards=[{"path": "../../etc", "n_clips": 3}])
    with pytest.raises(ProbeSetError, match="bad shard entry"):
        load_probe_set(tmp_path / "s")
    _tamper(tmp_path / "s", shards=[{"path": "shards/00000", "n_clips": 5}])
    with pytest.raises(ProbeSetError, match="holds .* clips, the manifest says 5|must number the 5 stored clips"):
        load_probe_set(tmp_path / "s").get(["c0000"])
    _tamper(tmp_path / "s", shards=[{"path": "shards/00000", "n_clips": 3}])
    f = tmp_path / "s/shards/00000/frames.npy"
    f.write_bytes(f.read_bytes()[:-10])
    with pytest.raises(ProbeSetError, match="frames.npy is truncated"):
        load_probe_set(tmp_path / "s").get(["c0002"])
    np.save(tmp_path / "s/shards/00000/states.npy", np.array([[None]] * 3, dtype=object), allow_pickle=True)
    with pytest.raises(ProbeSetError, match="not a C-ordered plain array"):
        load_probe_set(tmp_path / "s").get(["c0000"])
    with pytest.raises(ProbeSetError, match="empty set"):
        write_probe_set(tmp_path / "e", iter(()), META)
    assert not (tmp_path / "e").exists()


def test_writing_memory_does_not_grow_with_clips(tmp_path, monkeypatch):
    """The old writer stacked every clip in memory; the sharded one holds one shard."""
    monkeypatch.setattr("voe.io.shards.MAX_SHARD_CLIPS", 8)
    peaks = []
    for n in (40, 320):
        tracemalloc.start()
        write_probe_set(tmp_path / f"n{n}", _records(n), META)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    clip_bytes = T * S * S + T * K * F * 4
    assert peaks[1] - peaks[0] < 320 * clip_bytes / 4, peaks  # stacking would add 280 clips' bytes
