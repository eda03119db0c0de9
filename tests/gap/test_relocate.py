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


def test_a_store_made_before_the_second_bar_rescores_with_it():
    """Seed 7241's untouched run (before ``locate_local``) left the gust 7241143 ``consistent`` with
    nothing located; rescored, the second bar locates it, the stored count of the first bar's
    stretches still matches, and the verdict is ``unexplained``."""
    lines = (STORE.parent / "gap_bench_s52_seed7241.jsonl").read_text().splitlines()
    run = json.loads(lines[0])["run"]
    r = next(r for r in map(json.loads, lines[1:]) if r["seed"] == 7241143)
    assert r["verdict"] == "consistent" and r["located"] == 0 and "located_local" not in r
    new = relocate(r, run)
    assert new["verdict"] == "unexplained" and new["located"] == new["located_local"] > 0
