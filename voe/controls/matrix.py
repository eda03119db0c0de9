"""The specificity matrix: control x concept accuracy, verdicts, and where they break declarations.

Why: a probe is valid when models that know a law pass it and models that lack exactly that law
fail it, and nothing else. Reading the matrix cell by cell against what each control declares
shows, for every probe, whether it measures its concept (diagonal) and only its concept
(off-diagonal). Built from stored runs only.

Besides one row per control x concept, rows per control x concept x condition (``visible`` /
``occluded``) are computed; they are checked only where a control declares something about a
condition.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from voe.controls.spec import Control
from voe.scoring.metrics import accuracy
from voe.scoring.runs import Run
from voe.scoring.stats import bootstrap_ci, holm, permutation_pvalue
from voe.scoring.table import set_table
from voe.scoring.verdict import LEARNED, NOT_LEARNED, verdict


def outcome_ok(expect: str, verdict_: str, ci_low: float, ci_high: float) -> bool | None:
    """Does a cell match its declaration? ``None`` when nothing was declared."""
    if expect == "pass":
        return verdict_ == LEARNED
    if expect == "fail":
        return verdict_ == NOT_LEARNED
    if expect == "chance":
        return bool(ci_low <= 0.5 <= ci_high)
    return None


def _cells(ctrl: Control, sets: pd.DataFrame, n_boot: int) -> list[dict]:
    sets = sets.assign(condition=np.where(sets["visible_violation"].astype(bool), "visible", "occluded"))
    groups = [(c, None, g) for c, g in sets.groupby("concept", sort=True)]
    groups += [(c, cond, g) for (c, cond), g in sets.groupby(["concept", "condition"], sort=True)]
    rows = []
    for concept, cond, g in groups:
        acc = g["accuracy"].to_numpy()
        lo, hi = bootstrap_ci(acc, n_boot=n_boot)
        rows.append({"control": ctrl.name, "family": ctrl.family, "concept": concept,
                     "condition": cond or "all", "n_sets": len(acc), "accuracy": accuracy(acc),
                     "ci_low": lo, "ci_high": hi, "p_value": permutation_pvalue(acc),
                     "expected": ctrl.expectation(concept, cond)})
    return rows


def specificity_matrix(controls: Sequence[Control], runs: Sequence[Run], n_boot: int = 10_000) -> pd.DataFrame:
    """Rows per control x concept (``condition == 'all'``) and x condition, with verdicts.

    ``runs[i]`` must be the run of ``controls[i]``. p-values are Holm-corrected across the
    concept rows of a control (and separately across its condition rows).
    """
    if len(controls) != len(runs):
        raise ValueError("one run per control")
    rows: list[dict] = []
    for ctrl, run in zip(controls, runs, strict=True):
        cells = _cells(ctrl, set_table(run), n_boot)
        for part in ([r for r in cells if r["condition"] == "all"], [r for r in cells if r["condition"] != "all"]):
            if not part:
                continue
            for r, p in zip(part, holm(np.array([r["p_value"] for r in part])), strict=True):
                r["p_holm"] = float(p)
                r["verdict"], r["note"] = verdict(r["accuracy"], r["ci_low"], r["ci_high"], r["p_holm"])
                r["as_declared"] = outcome_ok(r["expected"], r["verdict"], r["ci_low"], r["ci_high"])
        rows += cells
    return pd.DataFrame(rows)


def mismatches(matrix: pd.DataFrame) -> pd.DataFrame:
    """Cells whose outcome differs from the declaration."""
    return matrix[matrix["as_declared"].eq(False)]
