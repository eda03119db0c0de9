"""The bench's result store: a cut-off run resumes, results of other code or arguments are refused."""

from __future__ import annotations

import json

import numpy as np
import pytest

import voe.gap.bench as bench
from voe.errors import DataError, VoeError
from voe.gap.bench_store import BenchStore
from voe.gap.truths import kind

RUN = {"cases": 4, "seed": 7, "clean": 2}


crossed: list[bool] = []  # the cross_fit flag each faked case was given


def _fake(calls):
    def run_case(args):
        seed, truth, _, _, _, _, nk, *opt = args
        calls.append(seed)
        crossed.append(bool(opt and opt[0]))
        return {"seed": seed, "truth": truth, "kind": kind(truth), "noise_kind": nk, "found": "none", "names": [],
                "group": [], "verdict": "consistent", "located": 0, "n_effects": 0, "dropped": [], "null_strength": 0,
                "before": 0.01, "after": 0.01, "param_error": float("nan"), "covered": np.bool_(True),
                "expressed": (np.int64(2), 5)}
    return run_case


def test_resume_runs_only_missing_cases(tmp_path, monkeypatch):
    calls: list[int] = []
    monkeypatch.setattr(bench, "run_case", _fake(calls))
    path = tmp_path / "r.jsonl"
    first = bench.run_bench(4, seed=7, clean=2, store=BenchStore(path, RUN))
    assert calls == [7000, 7001, 7002, 7003, 7004, 7005]
    # the machine stopped while the last case was being written: its line is cut off
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:-2]) + "\n" + lines[-1][:20])
    calls.clear()
    seen: list[int] = []
    again = bench.run_bench(4, seed=7, clean=2, store=BenchStore(path, RUN), progress=lambda r: seen.append(r["seed"]))
    assert calls == [7004, 7005]  # the cut-off line's case and the one never written
    assert [r["seed"] for r in again] == [r["seed"] for r in first] == seen
    assert again[0]["covered"] is True and again[0]["expressed"] == [2, 5]
    assert len(BenchStore(path, RUN).done) == 6


def test_other_arguments_or_code_refused(tmp_path, monkeypatch):
    path = tmp_path / "r.jsonl"
    BenchStore(path, RUN)
    with pytest.raises(DataError, match=r"r\.jsonl.*other run arguments \(cases\)"):
        BenchStore(path, {**RUN, "cases": 5})
    header = json.loads(path.read_text().splitlines()[0])
    path.write_text(json.dumps({**header, "code": "0" * 64}) + "\n")
    with pytest.raises(DataError, match="made by other voe code"):
        BenchStore(path, RUN)
    path.write_text("not json\n")
    with pytest.raises(DataError, match="not a JSON header"):
        BenchStore(path, RUN)


def test_broken_middle_line_refused(tmp_path):
    path = tmp_path / "r.jsonl"
    s = BenchStore(path, RUN)
    s.add({"seed": 1, "truth": "none"})
    path.write_text(path.read_text() + "{broken\n" + json.dumps({"seed": 2}) + "\n")
    with pytest.raises(DataError, match="line 3 is not JSON"):
        BenchStore(path, RUN)


def test_command_and_cli_print_the_same_lines_and_score_from_the_store(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from voe.cli.main import app
    from voe.gap.bench_run import BenchRun, bench_command

    calls: list[int] = []
    monkeypatch.setattr(bench, "run_case", _fake(calls))
    path = tmp_path / "r.jsonl"
    lines: list[str] = []
    bench_command(BenchRun(cases=3, seed=2, clean=1, clean_kinds=("coloured",)), results=str(path), echo=lines.append)
    assert calls == [2000, 2001, 2002, 2003]
    assert lines[0].startswith("  case 2000: true none") and "coloured" in lines[3]
    assert any(s.startswith("false discovery on clean (coloured noise): 0/1") for s in lines)
    calls.clear()
    res = CliRunner().invoke(app, ["gap", "bench", "--cases", "3", "--seed", "2", "--clean", "1",
                                   "--clean-kinds", "coloured", "--results", str(path), "--score-only"])
    assert res.exit_code == 0, res.output
    assert calls == []  # scored from the store, nothing run
    assert "scored from" in res.output and "4 of 4 planned cases stored" in res.output
    assert [s for s in lines if s.startswith("single-effect")] == \
        [s for s in res.output.splitlines() if s.startswith("single-effect")]


def test_a_resumed_command_does_not_show_the_stored_cases(tmp_path, monkeypatch):
    """An untouched run is not read before its end: resuming prints only the cases run now."""
    from voe.gap.bench_run import BenchRun, bench_command

    calls: list[int] = []
    monkeypatch.setattr(bench, "run_case", _fake(calls))
    path, run = tmp_path / "r.jsonl", BenchRun(cases=3, seed=2, clean=1, clean_kinds=("coloured",))
    bench_command(run, results=str(path), echo=lambda s: None)
    path.write_text("\n".join(path.read_text().splitlines()[:3]) + "\n")  # the header and two cases stored
    calls.clear()
    lines: list[str] = []
    out = bench_command(run, results=str(path), echo=lines.append)
    assert calls == [2002, 2003] and len(out) == 4
    assert lines[0] == f"resumed from {path}: 2 cases stored, their lines not shown again"
    assert [s.split(":")[0] for s in lines if s.startswith("  case")] == ["  case 2002", "  case 2003"]
    assert any(s.startswith("false discovery on clean (coloured noise)") for s in lines)  # the summary: all four


def test_unknown_truth_and_missing_store_are_one_line_errors(tmp_path):
    from tests.reliability.cli import assert_one_line_error, run_voe

    assert_one_line_error(run_voe("gap", "bench", "--truths", "lineardrag"),
                          "unknown bench truth 'lineardrag'; did you mean 'linear_drag'")
    missing = tmp_path / "none.jsonl"
    assert_one_line_error(run_voe("gap", "bench", "--results", missing, "--score-only"), str(missing), "no such file")
    assert not missing.exists()


def test_shards_of_a_job_array_score_together_as_the_whole_run(tmp_path, monkeypatch):
    from voe.gap.bench_run import BenchRun, bench_command

    calls: list[int] = []
    monkeypatch.setattr(bench, "run_case", _fake(calls))
    run = BenchRun(cases=5, seed=3, clean=2, compound=2)
    whole: list[str] = []
    bench_command(run, results=str(tmp_path / "all.jsonl"), echo=whole.append)
    calls.clear()
    files = []
    for i in range(3):  # three array tasks, each with its own store
        files.append(str(tmp_path / f"s{i}.jsonl"))
        bench_command(run, results=files[-1], shard=f"{i}/3", echo=lambda s: None)
    assert sorted(calls) == list(range(3000, 3009)) and len(calls) == 9  # every case once
    merged: list[str] = []
    bench_command(run, results=",".join(files), score_only=True, echo=merged.append)
    summary = lambda lines: [s for s in lines if not s.startswith(("  case", "scored from", "wall time"))]  # noqa: E731
    assert summary(merged) == summary(whole)
    with pytest.raises(DataError, match="holds shard"):  # a shard's store is not another shard's
        bench_command(run, results=files[0], shard="1/3", echo=lambda s: None)
    with pytest.raises(VoeError, match="--shard must be I/N"):
        bench_command(run, shard="3/3", echo=lambda s: None)


def _strict(text: str):
    """Parse as RFC 8259 JSON: NaN and Infinity are refused, as jq and JSON.parse refuse them."""
    def refuse(name):
        raise ValueError(f"not JSON: {name}")
    return json.loads(text, parse_constant=refuse)


def test_store_is_strict_json_and_a_case_stored_twice_merges(tmp_path, monkeypatch):
    monkeypatch.setattr(bench, "run_case", _fake([]))
    a, b = tmp_path / "a.jsonl", tmp_path / "b.jsonl"
    bench.run_bench(4, seed=7, clean=2, store=BenchStore(a, RUN))
    for line in a.read_text().splitlines():
        _strict(line)  # the nan parameter error is written as null
    assert json.loads(a.read_text().splitlines()[1])["param_error"] is None
    back = BenchStore(a, RUN).done[7000]
    assert np.isnan(back["param_error"]) and back["before"] == 0.01  # read back as a number
    b.write_bytes(a.read_bytes())  # the same cases stored by two shards, e.g. a task run twice
    from voe.gap.bench_store import read_stores

    done, _ = read_stores([a, b], RUN)  # nan != nan made equal cases look different
    assert sorted(done) == [7000, 7001, 7002, 7003, 7004, 7005]


def test_cross_fit_reaches_the_finder_and_keys_the_store(tmp_path, monkeypatch):
    from voe.gap.bench_run import BenchRun, bench_command

    monkeypatch.setattr(bench, "run_case", _fake([]))
    crossed.clear()
    plain, cross = BenchRun(cases=2, seed=5, clean=0), BenchRun(cases=2, seed=5, clean=0, cross_fit=True)
    assert "cross_fit" not in plain.store_key()  # stores made before the option still match their runs
    bench_command(plain, results=str(tmp_path / "p.jsonl"), echo=lambda s: None)
    assert crossed == [False, False]
    bench_command(cross, results=str(tmp_path / "c.jsonl"), echo=lambda s: None)
    assert crossed[2:] == [True, True]
    with pytest.raises(DataError, match=r"other run arguments \(cross_fit\)"):  # never pooled with plain runs
        bench_command(cross, results=str(tmp_path / "p.jsonl"), echo=lambda s: None)
