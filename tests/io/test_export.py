"""Export: exact redraw from stored states, opaque tables, answer key apart, mp4/png/IntPhys layouts."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from PIL import Image

from voe.concepts import CONCEPTS, get_concept
from voe.concepts.generate import generate_probe_set
from voe.errors import VoeError
from voe.io.clipkey import clip_key, set_key
from voe.io.export import export_probe_set
from voe.io.probeset import load_probe_set
from voe.io.provenance import sha256_file
from voe.sim.render import RGB_SLOTS, render_clip
from voe.sim.scene import SimConfig


@pytest.fixture(scope="module")
def probes64(tmp_path_factory):
    """Two sets (one visible, one occluded violation) of every concept at 64 px."""
    out = tmp_path_factory.mktemp("p64") / "set"
    generate_probe_set(out, CONCEPTS.ids(), 2, 3, SimConfig(size=64))
    return out


def _first_of_kind(kind: str) -> str | None:
    return next((c for c in CONCEPTS.ids() if get_concept(c).kind == kind), None)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """One quadruplet concept and one pair concept (if any), one set each (for the slower mp4 path)."""
    out = tmp_path_factory.mktemp("small") / "set"
    ids = [c for c in (_first_of_kind("quadruplet"), _first_of_kind("pair")) if c]
    generate_probe_set(out, ids, 1, 0, SimConfig(size=32))
    return out


def test_redraw_from_stored_states_is_byte_identical_at_64px(probes64):
    ps = load_probe_set(probes64)
    data = ps.get(list(ps.index.clip_id))
    assert set(ps.index.concept) == set(CONCEPTS.ids())
    for i, geo in enumerate(ps.index.geometry):
        again = render_clip(data["states"][i], data["present"][i], json.loads(geo), 64)
        assert np.array_equal(again, data["frames"][i]), ps.index.clip_id.iloc[i]


def test_native_size_is_drawn_not_upscaled(probes64):
    ps = load_probe_set(probes64)
    d = ps.get(["permanence-0000-A"])
    geo = json.loads(ps.index.set_index("clip_id").loc["permanence-0000-A", "geometry"])
    f64 = d["frames"][0].astype(float)  # (T, 64, 64)
    f128 = render_clip(d["states"][0], d["present"][0], geo, 128).astype(float)
    up = np.kron(f64, np.ones((1, 2, 2)))
    assert (f128 != up).mean() > 0.01  # edges are sharper than a 2x upscale
    box = f128.reshape(len(f128), 64, 2, 64, 2).mean(axis=(2, 4))
    assert np.abs(box - f64).mean() < 1.0  # but it is the same picture


def test_rgb_gives_each_slot_its_colour(probes64):
    ps = load_probe_set(probes64)
    data = ps.get(list(ps.index.clip_id))
    i = int(np.argmax(data["present"].sum(axis=2).max(axis=1)))  # the clip showing most objects at once
    st, pr = data["states"][i], data["present"][i]
    rgb = render_clip(st, pr, json.loads(ps.index.geometry.iloc[i]), 96, rgb=True)  # (T, 96, 96, 3)
    assert rgb.shape == (len(st), 96, 96, 3)
    t = int(np.argmax(pr.sum(1)))
    checked = 0
    for k in np.flatnonzero(pr[t]):
        x, y = st[t, k, 0], st[t, k, 1]
        if not (0.5 < x < 9.5 and 0.5 < y < 9.5):
            continue
        px = rgb[t, int((10 - y) / 10 * 96), int(x / 10 * 96)].astype(float)  # the object's centre
        np.testing.assert_allclose(px, np.array(RGB_SLOTS[k]) * st[t, k, 10] * 255, atol=3)
        checked += 1
    assert checked >= 2


def test_flat_png_tables_keys_and_hashes(probes64, tmp_path):
    out = tmp_path / "x"
    m = export_probe_set(probes64, out, fmt="png", size=48, rgb=True)
    ps = load_probe_set(probes64)
    meta = pd.read_parquet(out / "metadata.parquet")
    ans = pd.read_parquet(out / "answers.parquet")
    assert len(meta) == len(ps.index) == m["n_clips"]
    assert list(meta.clip_key) == sorted(meta.clip_key)
    assert {"clip_key", "path", "concept", "condition", "set_key", "onset_frame"} <= set(meta.columns)
    assert not {"role", "variant", "clip_id", "set_id", "is_possible"} & set(meta.columns)
    sha = ps.manifest_sha256
    assert m["source"]["manifest_sha256"] == sha
    assert sorted(ans.clip_key) == sorted(clip_key(sha, c) for c in ps.index.clip_id)
    assert set(ans.set_key) == {set_key(sha, s) for s in ps.index.set_id}
    pd.testing.assert_frame_equal(pd.read_csv(out / "metadata.csv"), meta, check_dtype=False)
    for rel, h in m["files"].items():
        assert sha256_file(out / rel) == h
    assert json.loads((out / "manifest.json").read_text())["files"] == m["files"]
    # the clip's frames, natively at 48 px in colour, named by key only
    row = meta.iloc[0]
    assert row.path == f"clips/{row.clip_key[:2]}/{row.clip_key}"
    frames = sorted((out / row.path).iterdir())
    assert [f.name for f in frames[:2]] == ["000.png", "001.png"] and len(frames) == row.n_frames
    assert np.asarray(Image.open(frames[0])).shape == (48, 48, 3)
    # nothing in the exported tree names a role or a clip id
    names = " ".join(p.name for p in out.rglob("*"))
    assert "possible" not in names and "permanence-0" not in names


def test_datasets_load_metadata_offline(probes64, tmp_path):
    out = tmp_path / "x"
    export_probe_set(probes64, out, fmt="png", size=32)
    code = ("import datasets, sys; d = datasets.load_dataset('parquet', data_files=sys.argv[1], "
            "split='train'); print(len(d), sorted(d.column_names))")
    env = {"HF_DATASETS_OFFLINE": "1", "HF_HUB_OFFLINE": "1", "HF_HOME": str(tmp_path / "hf"),
           "PATH": "/usr/bin:/bin"}
    res = subprocess.run([sys.executable, "-c", code, str(out / "metadata.parquet")], env=env,
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.startswith(f"{len(load_probe_set(probes64).index)} ") and "clip_key" in res.stdout


def test_mp4_is_near_lossless_and_reproducible(small, tmp_path):
    pytest.importorskip("imageio_ffmpeg")
    from voe.io.video import read_mp4

    a = export_probe_set(small, tmp_path / "a", fmt="mp4", size=40, rgb=True)
    b = export_probe_set(small, tmp_path / "b", fmt="mp4", size=40, rgb=True, jobs=2)
    assert a["files"] == b["files"]  # same bytes, whatever jobs is
    ps = load_probe_set(small)
    ans = pd.read_parquet(tmp_path / "a" / "answers.parquet").set_index("clip_key")
    meta = pd.read_parquet(tmp_path / "a" / "metadata.parquet")
    for row in meta.itertuples():
        cid = ans.loc[row.clip_key, "clip_id"]
        d = ps.get([cid])
        geo = json.loads(ps.index.set_index("clip_id").loc[cid, "geometry"])
        want = render_clip(d["states"][0], d["present"][0], geo, 40, rgb=True)
        got = read_mp4(tmp_path / "a" / row.path)
        assert got.shape == want.shape
        assert np.abs(got.astype(int) - want).max() <= 3


def test_intphys_layout(small, tmp_path):
    out = tmp_path / "ip"
    m = export_probe_set(small, out, fmt="png", size=32, layout="intphys")
    quad, pair = _first_of_kind("quadruplet"), _first_of_kind("pair")
    block = quad.split("-v")[0].lower()
    assert m["intphys"]["quadruplet_blocks"] == [block]
    runs = sorted(p.name for p in (out / block / "01").iterdir())
    assert runs == ["1", "2", "3", "4"]
    if pair:
        pblock = pair.split("-v")[0].lower()
        assert m["intphys"]["pair_blocks"] == [pblock]
        assert sorted(p.name for p in (out / pblock / "01").iterdir()) == ["1", "2"]
    ans = pd.read_parquet(out / "answers.parquet").set_index("clip_key")
    possible = []
    for run in runs:
        d = out / block / "01" / run
        assert (d / "scene" / "scene_001.png").exists() and (d / "scene" / "scene_040.png").exists()
        header = json.loads((d / "status.json").read_text())["header"]
        assert header["is_possible"] == bool(ans.loc[header["clip_key"], "is_possible"])
        possible.append(header["is_possible"])
    assert sorted(possible) == [False, False, True, True]


@pytest.mark.parametrize("kw, msg", [
    ({"fmt": "avi"}, "unknown --format 'avi'"),
    ({"size": 8}, "--size 8"),
    ({"layout": "intphys", "fmt": "mp4"}, "--layout intphys"),
])
def test_bad_options_are_one_line_errors(small, tmp_path, kw, msg):
    with pytest.raises(VoeError, match=msg.replace("'", ".")):
        export_probe_set(small, tmp_path / "x", **{"fmt": "png", **kw})
    assert not (tmp_path / "x").exists()


def test_cli_refuses_existing_output(small, tmp_path):
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / "keep.txt").write_text("mine")
    res = subprocess.run([sys.executable, "-m", "voe", "probes", "export", str(small), "--out",
                          str(tmp_path / "x"), "--format", "png", "--size", "32"],
                         capture_output=True, text=True)
    assert res.returncode == 1
    assert res.stderr.strip().count("\n") == 0 and "already exists" in res.stderr
    assert (tmp_path / "x" / "keep.txt").read_text() == "mine"
