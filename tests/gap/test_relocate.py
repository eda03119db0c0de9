"""bench/gap_relocate.py's rescore (voe.gap.bench_relocate) on a case of session 25's stored
untouched run (shipped in docs/bench-runs): exact where the location is unchanged, refused where it
is not."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from voe.errors import DataError
from voe.gap.bench_relocate import relocate

STORE = Path(__file__).resolve().parents[2] / "docs" / "bench-runs" / "gap_bench_s25_seed2250.jsonl"


def _stored(seed: int) -> tuple[dict, dict]:
    lines = STORE.read_text().splitlines()
    return json.loads(lines[0])["run"], next(r for r in map(json.loads, lines[1:]) if r["seed"] == seed)


def test_a_stored_case_relocates_to_its_own_location_and_a_changed_one_is_refused():
    run, r = _stored(2250144)  # a floor patch read consistent (located stretches, departure p above ALPHA)
    assert r["n_effects"] == 0 and r["located"] > 0
    new = relocate(r, run)
    assert new["located"] == r["located"]
    assert new["verdict"] == "consistent" and new["relocated"] > 0.5  # 0.87: one of session 28's misses
    with pytest.raises(DataError, match="location differs"):
        relocate({**r, "located": r["located"] + 1}, run)
