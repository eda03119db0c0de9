"""Hypothesis strategies that damage files the way the world does, and the one property checked.

The property (``only_voe_errors``): a reader given any damaged input either works or raises one
of voe's own errors (``VoeError``) with a one-line message; any other exception is a traceback a
user would see, and fails the test. Each fuzz module builds its valid base object once and draws
mutations of it: truncated, byte-flipped, empty or foreign bytes; JSON values swapped for wrong
types, NaN, huge or negative numbers and unicode; table columns dropped, retyped or poisoned;
arrays with the wrong dtype or shape.
"""

from __future__ import annotations

import io
import json
import math
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from voe.errors import VoeError

EXAMPLES = 200
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])


COLLECT: list[str] | None = None  # set to a list to collect failures instead of raising (triage)


def only_voe_errors(fn: Callable[[], Any]) -> Any:
    """Run ``fn``; a ``VoeError`` must be one line, anything else propagates (fails the test)."""
    try:
        return fn()
    except VoeError as exc:
        msg = str(exc)
        if COLLECT is not None and (not msg or "\n" in msg):
            COLLECT.append(f"multi-line {type(exc).__name__}: {msg[:200]!r}")
            return exc
        assert msg and "\n" not in msg, f"{type(exc).__name__} spans lines: {msg!r}"
        return exc
    except Exception as exc:
        if COLLECT is None:
            raise
        import traceback

        tb = [f for f in traceback.extract_tb(exc.__traceback__) if "/voe/" in f.filename]
        where = f"{tb[-1].filename.split('/voe/')[-1]}:{tb[-1].lineno}" if tb else "?"
        COLLECT.append(f"{type(exc).__name__} at {where}: {str(exc)[:120]}")


# -- values ---------------------------------------------------------------------------------
weird_numbers = st.sampled_from([0, -1, -(2**63), 2**63, 2**64 + 1, 10**30, -1e300, 1e300, 1e-320,
                                 math.nan, math.inf, -math.inf, 0.5, -0.0, True, False])
weird_text = st.sampled_from(["", " ", "é", "日本語", "\u202e", "\x00", "NaN", "inf", "-1", "1e400",
                              "../../etc/passwd", "/etc/passwd", "a" * 300, "None", "[]", "{}"])
scalars = st.one_of(st.none(), weird_numbers, weird_text, st.integers(), st.floats(),
                    st.text(max_size=20))
json_values = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                             st.dictionaries(st.text(max_size=5), inner, max_size=3)),
                           max_leaves=6)


# -- bytes ----------------------------------------------------------------------------------
@st.composite
def damaged_bytes(draw: st.DrawFn, base: bytes) -> bytes:
    """``base`` truncated, flipped, spliced, emptied or replaced."""
    kind = draw(st.sampled_from(["truncate", "flip", "insert", "empty", "random", "text", "double"]))
    n = len(base)
    if kind == "truncate":
        return base[:draw(st.integers(0, max(n - 1, 0)))]
    if kind == "flip" and n:
        data = bytearray(base)
        for _ in range(draw(st.integers(1, 8))):
            i = draw(st.integers(0, n - 1))
            data[i] = draw(st.integers(0, 255))
        return bytes(data)
    if kind == "insert":
        i = draw(st.integers(0, n))
        return base[:i] + draw(st.binary(min_size=1, max_size=32)) + base[i:]
    if kind == "empty":
        return b""
    if kind == "text":
        return draw(st.text(max_size=200)).encode("utf-8", "surrogatepass")
    if kind == "double":
        return base + base
    return draw(st.binary(max_size=256))


# -- JSON documents -------------------------------------------------------------------------
def _paths(doc: Any, prefix: tuple = ()) -> list[tuple]:
    out = [prefix]
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += _paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:4]):
            out += _paths(v, (*prefix, i))
    return out


def _set(doc: Any, path: tuple, value: Any, delete: bool = False) -> Any:
    if not path:
        return value
    parent = doc
    for k in path[:-1]:
        parent = parent[k]
    if delete:
        del parent[path[-1]]
    else:
        parent[path[-1]] = value
    return doc


@st.composite
def damaged_doc(draw: st.DrawFn, base: Any) -> Any:
    """``base`` (a JSON-able document) with one to three values replaced by weird ones or deleted."""
    doc = json.loads(json.dumps(base))
    for _ in range(draw(st.integers(1, 3))):
        paths = _paths(doc)
        path = draw(st.sampled_from(paths))
        delete = bool(path) and draw(st.booleans())
        doc = _set(doc, path, None if delete else draw(json_values), delete)
    return doc


@st.composite
def damaged_json(draw: st.DrawFn, base: Any) -> bytes:
    """``damaged_doc`` as JSON text (NaN and Infinity included), or damaged bytes."""
    if draw(st.integers(0, 4)) == 0:
        return draw(damaged_bytes(json.dumps(base).encode()))
    return json.dumps(draw(damaged_doc(base)), allow_nan=True).encode()


# -- tables ---------------------------------------------------------------------------------
@st.composite
def damaged_frame(draw: st.DrawFn, base: pd.DataFrame) -> pd.DataFrame:
    """``base`` with columns dropped, retyped or poisoned, rows removed or duplicated."""
    df = base.copy()
    for _ in range(draw(st.integers(1, 3))):
        kind = draw(st.sampled_from(["drop", "retype", "poison", "rows", "empty", "dup", "extra"]))
        cols = list(df.columns)
        if kind == "drop" and cols:
            df = df.drop(columns=[draw(st.sampled_from(cols))])
        elif kind == "retype" and cols:
            c = draw(st.sampled_from(cols))
            to = draw(st.sampled_from(["str", "float", "bool", "int", "bytes"]))
            if to == "str":
                df[c] = df[c].astype(str)
            elif to == "bytes":
                df[c] = [str(v).encode() for v in df[c]]
            elif to == "float":
                df[c] = np.linspace(-1e300, 1e300, len(df)) if len(df) else []
            elif to == "bool":
                df[c] = np.arange(len(df)) % 2 == 0
            else:
                df[c] = np.arange(len(df)) * -7
        elif kind == "poison" and cols and len(df):
            c = draw(st.sampled_from(cols))
            i = draw(st.integers(0, len(df) - 1))
            v = draw(st.one_of(weird_numbers, weird_text, st.none()))
            col = df[c].astype(object)
            col.iloc[i] = v
            try:
                df[c] = pd.Series(list(col), index=df.index).infer_objects()
            except (TypeError, ValueError):
                df[c] = col
        elif kind == "rows" and len(df):
            df = df.iloc[: draw(st.integers(0, len(df) - 1))]
        elif kind == "empty":
            df = df.iloc[:0]
        elif kind == "dup" and len(df):
            df = pd.concat([df, df.iloc[[draw(st.integers(0, len(df) - 1))]]])
        elif kind == "extra":
            df["extra é"] = "x"
    return df.reset_index(drop=True)


def parquet_bytes(df: pd.DataFrame) -> bytes | None:
    """The frame as parquet, or None if pyarrow cannot store it (then the example is moot)."""
    buf = io.BytesIO()
    try:
        df.to_parquet(buf, index=False)
    except Exception:  # noqa: BLE001 - mixed object columns pyarrow refuses to write
        return None
    return buf.getvalue()


# -- arrays ---------------------------------------------------------------------------------
@st.composite
def damaged_array(draw: st.DrawFn, base: np.ndarray) -> bytes:
    """``base`` as .npy with the wrong dtype, shape or values, or damaged bytes."""
    kind = draw(st.sampled_from(["dtype", "shape", "values", "bytes", "object", "scalar"]))
    a = np.array(base)
    if kind == "dtype":
        a = a.astype(draw(st.sampled_from([np.float64, np.int64, np.uint8, np.float16, bool, np.complex64])))
    elif kind == "shape":
        a = draw(st.sampled_from([a.reshape(-1), a[:0], a[..., :1], a[None], a[:, :1] if a.ndim > 1 else a[:1]]))
    elif kind == "values" and a.dtype.kind == "f":
        a = a.copy()
        a.flat[draw(st.integers(0, a.size - 1))] = draw(st.sampled_from([np.nan, np.inf, -np.inf, 1e38, -1e38]))
    elif kind == "object":
        buf = io.BytesIO()
        np.save(buf, np.array([{"x": 1}], dtype=object), allow_pickle=True)
        return buf.getvalue()
    elif kind == "scalar":
        a = np.array(draw(st.sampled_from([0, 1.5, np.nan])))
    buf = io.BytesIO()
    np.save(buf, a, allow_pickle=False)
    data = buf.getvalue()
    return draw(damaged_bytes(data)) if kind == "bytes" else data


def lay_out(files: dict[str, bytes], d: Path) -> Path:
    """Write ``files`` (relative path -> bytes) into a fresh folder ``d`` and return it."""
    shutil.rmtree(d, ignore_errors=True)
    d.mkdir(parents=True)
    for rel, data in files.items():
        (d / rel).parent.mkdir(parents=True, exist_ok=True)
        (d / rel).write_bytes(data)
    return d
