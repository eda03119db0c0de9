"""Strict JSON writing: what voe writes parses with a strict parser, and odd values are named."""

from __future__ import annotations

import json

import numpy as np
import pytest

from voe.io import jsonio


def _strict(text: str):
    def refuse(name):
        raise ValueError(f"not JSON: {name}")
    return json.loads(text, parse_constant=refuse)


def test_non_finite_numbers_become_null_and_numpy_becomes_plain():
    obj = {"a": float("nan"), "b": [np.float64(np.inf), -np.inf, 1.5], "c": np.arange(3), "d": np.int64(4),
           "e": (np.float32(np.nan), True), "f": {"g": np.array([np.nan, 2.0])}, "h": None, "s": "NaN"}
    text = jsonio.dumps(obj, sort_keys=True)
    assert _strict(text) == {"a": None, "b": [None, None, 1.5], "c": [0, 1, 2], "d": 4, "e": [None, True],
                             "f": {"g": [None, 2.0]}, "h": None, "s": "NaN"}
    assert jsonio.dumps({"x": 1.0}, indent=1) == json.dumps({"x": 1.0}, indent=1)  # finite data: same bytes as before


def test_unwritable_value_is_named_and_default_still_applies():
    with pytest.raises(TypeError, match="set"):
        jsonio.dumps({"x": {1, 2}})
    assert _strict(jsonio.dumps({"p": object}, default=lambda o: "obj")) == {"p": "obj"}


def test_nan_if_none_reads_null_and_legacy_nan_back():
    assert np.isnan(jsonio.nan_if_none(None)) and np.isnan(jsonio.nan_if_none(float("nan")))
    assert jsonio.nan_if_none(2) == 2.0
