"""Fuzzed outside surprise tables (``voe score --surprises FILE``, csv and parquet)."""

from __future__ import annotations

import io

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from voe.io.clipkey import clip_key
from voe.io.probeset import load_probe_set
from voe.scoring.external import read_table, table_to_nll

from .mutate import FUZZ, damaged_bytes, damaged_frame, only_voe_errors, parquet_bytes


@pytest.fixture(scope="module")
def base(tiny_probes):
    ps = load_probe_set(tiny_probes)
    keys = [clip_key(ps.manifest_sha256, c) for c in ps.index.sort_values("row")["clip_id"]]
    T = int(ps.manifest["n_frames"])
    rng = np.random.default_rng(0)
    table = pd.DataFrame({"clip_key": np.repeat(keys, 3), "frame": np.tile([0, T // 2, T - 1], len(keys)),
                          "surprise": rng.random(3 * len(keys))})
    return keys, T, table


def test_base_table_reads(base, scratch):
    keys, T, table = base
    p = scratch / "s.csv"
    table.to_csv(p, index=False)
    assert np.isfinite(table_to_nll(p, read_table(p), keys, T)).sum() == len(table)


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
@FUZZ
@given(data=st.data())
def test_surprise_table(base, scratch, suffix, data):
    keys, T, table = base
    p = scratch / f"s{suffix}"
    if data.draw(st.booleans()):
        df = data.draw(damaged_frame(table))
        p.write_bytes(df.to_csv(index=False).encode() if suffix == ".csv" else (parquet_bytes(df) or b""))
    else:
        buf = io.BytesIO()
        table.to_csv(buf, index=False) if suffix == ".csv" else table.to_parquet(buf, index=False)
        p.write_bytes(data.draw(damaged_bytes(buf.getvalue())))
    only_voe_errors(lambda: table_to_nll(p, read_table(p), keys, T))
