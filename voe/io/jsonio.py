"""Strict JSON for every file voe writes: a missing number is ``null``, never ``NaN``.

Why: Python's ``json`` writes ``NaN`` and ``Infinity`` by default. Python and pandas read them
back, but they are not JSON (RFC 8259), so ``jq``, JavaScript's ``JSON.parse`` and most other
tools reject the whole file, and a researcher who opens ``gap.json`` or a bench store outside
Python gets nothing. They also break equality: two reads of the same stored ``NaN`` compare
unequal, so the same bench case stored by two shards looked different. ``dumps`` writes a
non-finite float as ``null`` and refuses anything else it cannot write. Readers that need the
number back use ``nan_if_none``.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np


def jsonable(obj: Any) -> Any:
    """``obj`` with numpy scalars and arrays as plain numbers and lists, tuples as lists and
    non-finite floats as None, recursively (dict keys left as they are)."""
    if isinstance(obj, dict):
        return {k: jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        return jsonable(obj.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dumps(obj: Any, **kwargs: Any) -> str:
    """``json.dumps`` of ``jsonable(obj)`` that can only produce strict JSON.

    Raises:
        TypeError: for a value JSON has no form for (the message names its type).
    """
    return json.dumps(jsonable(obj), allow_nan=False, **kwargs)


def nan_if_none(value: Any) -> float:
    """A stored number read back: ``null`` (and a legacy ``NaN``) as ``nan``."""
    return float("nan") if value is None else float(value)
