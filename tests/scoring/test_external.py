"""`voe score --surprises`: outside surprise tables become ordinary runs; bad tables get one line."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from voe.errors import VoeError
from voe.io.clipkey import clip_key
from voe.io.probeset import load_probe_set
from voe.scoring import load_run
from voe.scoring.external import score_surprises
from voe.scoring.table import concept_table


@pytest.fixture(scope="module")
def table(fake_runs, synth_probes) -> pd.DataFrame:
    """The random model's stored surprise, as an outside tool would write it (keys, no ids)."""
    sha = load_probe_set(synth_probes).manifest_sha256
    frames = pd.read_parquet(fake_runs["random-0"] / "frames.parquet")
    return pd.DataFrame({"clip_key": [clip_key(sha, c) for c in frames["clip_id"]],
                         "frame": frames["t"], "surprise": frames["nll"]}).sample(frac=1.0, random_state=0)


@pytest.mark.parametrize("fmt", ["parquet", "csv"])
def test_outside_table_gives_the_same_run(fmt, table, fake_runs, synth_probes, tmp_path):
    path = tmp_path / f"s.{fmt}"
    table.to_parquet(path) if fmt == "parquet" else table.to_csv(path, index=False)
    meta = score_surprises(synth_probes, path, tmp_path / "run", kind="error", name="random-0")
    assert meta["surprise_kind"] == "error" and meta["model"]["surprises"]["file"] == path.name
    for f in ("frames.parquet", "clips.parquet"):
        assert (tmp_path / "run" / f).read_bytes() == (fake_runs["random-0"] / f).read_bytes(), f
    mine = concept_table([load_run(tmp_path / "run")], n_boot=300)
    ref = concept_table([load_run(fake_runs["random-0"])], n_boot=300)
    pd.testing.assert_frame_equal(mine.drop(columns="relative_surprise"), ref.drop(columns="relative_surprise"))


def test_one_value_per_clip(synth_probes, tmp_path):
    ps = load_probe_set(synth_probes)
    idx = ps.index
    # surprise 2 for impossible clips, 1 for possible ones: perfect; written with numeric-looking keys too
    df = pd.DataFrame({"clip_key": [clip_key(ps.manifest_sha256, c) for c in idx["clip_id"]],
                       "surprise": np.where(idx["role"] == "impossible", 2.0, 1.0)})
    df.to_csv(tmp_path / "s.csv", index=False)
    score_surprises(synth_probes, tmp_path / "s.csv", tmp_path / "run")
    run = load_run(tmp_path / "run")
    assert (run.clips["n_scored"] == 1).all() and np.isnan(run.nll[:, :-1]).all()
    assert (concept_table([run], n_boot=200)["accuracy"] == 1.0).all()


def _broken(table: pd.DataFrame):
    t = table.reset_index(drop=True)
    yield "missing column", t.drop(columns="surprise"), "lacks column"
    yield "unknown key", t.assign(clip_key=["0123456789abcdef"] + list(t["clip_key"][1:])), "not clips of this probe set"
    yield "missing clips", t[t["clip_key"] != t["clip_key"][0]], "have no surprise"
    yield "duplicate rows", pd.concat([t, t.iloc[:1]]), "appears more than once"
    yield "NaN", t.assign(surprise=[np.nan] + list(t["surprise"][1:])), "finite number"
    yield "text surprise", t.assign(surprise=["high"] + [str(v) for v in t["surprise"][1:]]), "must hold numbers"
    yield "text frame", t.assign(frame=t["frame"].astype(str)), "must hold numbers"
    yield "fractional frame", t.assign(frame=[1.5] + list(t["frame"][1:])), "whole numbers"
    yield "frame out of range", t.assign(frame=[999] + list(t["frame"][1:])), "outside 0.."
    yield "integer keys", t.assign(clip_key=list(range(len(t)))), "text keys"
    yield "no rows", t.iloc[:0], "no rows"


@pytest.mark.parametrize("case", [c[0] for c in _broken(pd.DataFrame({"clip_key": ["a"], "frame": [0], "surprise": [1.0]}))])
def test_malformed_tables_get_one_line_naming_the_file(case, table, synth_probes, tmp_path):
    _, df, needle = next(c for c in _broken(table) if c[0] == case)
    path = tmp_path / "bad.parquet"
    df.to_parquet(path)
    with pytest.raises(VoeError, match=needle) as err:
        score_surprises(synth_probes, path, tmp_path / "run")
    assert str(path) in str(err.value) and "\n" not in str(err.value)
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("name, data, needle", [("s.parquet", b"not parquet at all", "cannot be read"),
                                                ("s.csv", b"", "cannot be read"),
                                                ("s.json", b"{}", "unknown suffix")])
def test_unreadable_files_on_the_cli(name, data, needle, synth_probes, tmp_path):
    (tmp_path / name).write_bytes(data)
    res = subprocess.run([sys.executable, "-m", "voe", "score", "--probes", str(synth_probes), "--surprises",
                          str(tmp_path / name), "--out", str(tmp_path / "run")], capture_output=True, text=True)
    lines = res.stderr.strip().splitlines()
    assert res.returncode == 1 and len(lines) == 1, res.stderr
    assert lines[0].startswith("voe: error: surprise table") and name in lines[0] and needle in lines[0]


def test_surprise_options_need_a_table(synth_probes, tmp_path):
    res = subprocess.run([sys.executable, "-m", "voe", "score", "--probes", str(synth_probes), "--model",
                          "voe.testing:BlindModel", "--surprise-kind", "error", "--out", str(tmp_path / "r")],
                         capture_output=True, text=True)
    assert res.returncode == 1 and "--surprise-kind and --name go with --surprises" in res.stderr


def test_fuzzed_tables_give_only_one_line_errors(synth_probes, tmp_path):
    """Any table (types, NaN, huge and negative values, unicode, empty, damaged bytes): a run or a
    one-line VoeError naming the file, never another exception."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from voe.scoring.external import read_table, table_to_nll

    ps = load_probe_set(synth_probes)
    keys = [clip_key(ps.manifest_sha256, c) for c in ps.index.sort_values("row")["clip_id"]]
    cell = st.one_of(st.sampled_from(keys), st.text(max_size=20), st.integers(-2**70, 2**70),
                     st.floats(allow_nan=True, allow_infinity=True), st.booleans(), st.none(),
                     st.complex_numbers(allow_nan=True))
    column = st.lists(cell, min_size=0, max_size=6)
    names = st.sampled_from(["clip_key", "frame", "surprise", "extra", "é"])

    @settings(max_examples=200, deadline=None, suppress_health_check=list(HealthCheck))
    @given(cols=st.dictionaries(names, column, max_size=4), fmt=st.sampled_from(["csv", "parquet"]),
           junk=st.binary(max_size=64), damage=st.booleans())
    def check(cols, fmt, junk, damage):
        n = max((len(v) for v in cols.values()), default=0)
        df = pd.DataFrame({k: (v + [None] * n)[:n] for k, v in cols.items()})
        path = tmp_path / f"t.{fmt}"
        try:
            df.to_parquet(path) if fmt == "parquet" else df.to_csv(path, index=False)
        except Exception:  # pyarrow cannot store every mix of Python objects; write junk instead
            damage = True
        if damage:
            path.write_bytes(junk)
        try:
            table_to_nll(path, read_table(path), keys, 24)
        except VoeError as exc:
            assert str(path) in str(exc) and "\n" not in str(exc)

    check()


def test_scoring_a_table_never_imports_torch(table, synth_probes, tmp_path):
    table.to_parquet(tmp_path / "s.parquet")
    code = (f"import sys; from voe.cli.main import main; sys.argv = ['voe', 'score', '--probes', "
            f"{str(synth_probes)!r}, '--surprises', {str(tmp_path / 's.parquet')!r}, '--out', "
            f"{str(tmp_path / 'run')!r}]\ntry:\n    main()\nexcept SystemExit:\n    pass\n"
            "assert not [m for m in sys.modules if m.split('.')[0] == 'torch'], 'torch imported'")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert res.returncode == 0 and (tmp_path / "run" / "run.json").is_file(), res.stderr


def test_export_then_outside_tool_then_score(tiny_probes, tmp_path):
    """The round trip a user makes: export png clips, score them with an outside tool that sees only
    the export (metadata.parquet and files), score its table, report ranks like any run."""
    from PIL import Image

    from voe.io.export import export_probe_set

    export_probe_set(tiny_probes, tmp_path / "ex", fmt="png", size=32)
    meta = pd.read_parquet(tmp_path / "ex" / "metadata.parquet")
    rows = []
    for key, rel in zip(meta["clip_key"], meta["path"], strict=True):  # the "outside tool"
        files = sorted((tmp_path / "ex" / rel).rglob("*.png"))
        frames = np.stack([np.asarray(Image.open(f), dtype=np.float64) for f in files])  # (T, H, W[, 3])
        change = np.abs(np.diff(frames, axis=0)).mean(axis=tuple(range(1, frames.ndim)))  # (T-1,)
        rows += [{"clip_key": key, "frame": t + 1, "surprise": float(c)} for t, c in enumerate(change)]
    pd.DataFrame(rows).to_csv(tmp_path / "s.csv", index=False)
    res = subprocess.run([sys.executable, "-m", "voe", "score", "--probes", str(tiny_probes), "--surprises",
                          str(tmp_path / "s.csv"), "--surprise-kind", "error", "--name", "motion",
                          "--out", str(tmp_path / "run")], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    run = load_run(tmp_path / "run")
    ps = load_probe_set(tiny_probes)
    assert run.surprise_kind == "error" and run.label == "motion" and len(run.clips) == len(ps)
    assert np.isnan(run.nll[:, 0]).all() and not np.isnan(run.nll[:, 1:]).any()
    t = concept_table([run], n_boot=200)
    assert len(t) == ps.index["concept"].nunique() and t["accuracy"].between(0, 1).all()
