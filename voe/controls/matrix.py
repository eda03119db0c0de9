"""The specificity matrix: control x concept accuracy, verdicts, and where they break declarations.

Why: a probe is valid when models that know a law pass it and models that lack exactly that law
fail it, and nothing else. Reading the matrix cell by cell against what each control declares
shows, for every probe, whether it measures its concept (diagonal) and only its concept
(off-diagonal). Built from runs only (stored, or in memory for statistics of the probe set).

Rows: per control x concept over the sets that carry the concept's verdict (``condition ==
'all'``), and per control x concept x condition (every condition, perceptual ones included).

A cell *could not have failed* when its outcome was fixed before the run: a control that is a
constant on the concept's clips, or a ``chance`` declaration of a control that ties by
construction on a balance (``Control.invariant_to``) that every set of the cell reaches. Such
cells are reported apart: they are checks of the construction, not evidence.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from voe.controls.spec import Control
from voe.scoring.metrics import accuracy
from voe.scoring.runs import Run
from voe.scoring.stats import bootstrap_ci, permutation_pvalue
from voe.scoring.table import halves_cells, judge, set_table
from voe.scoring.verdict import LEARNED, NOT_LEARNED, set_conditions

#: Claims of *no* knowledge hold on every part of a concept: a verdict-carrying condition
#: inherits them from the concept unless it declares its own.
INHERITED = ("chance", "not-learned")


def outcome_ok(expect: str, verdict_: str, ci_low: float, ci_high: float) -> bool | None:
    """Does a cell match its declaration? ``None`` when nothing was declared."""
    if expect == "pass":
        return verdict_ == LEARNED
    if expect == "fail":
        return verdict_ == NOT_LEARNED
    if expect == "chance":
        return bool(ci_low <= 0.5 <= ci_high)
    if expect == "not-learned":
        return verdict_ != LEARNED
    return None


def two_sided_pvalue(set_scores: np.ndarray) -> float:
    """Sign-flip p-value that accuracy differs from chance in either direction (capped at 1)."""
    s = np.asarray(set_scores, dtype=np.float64)
    return min(1.0, 2 * min(permutation_pvalue(s), permutation_pvalue(1.0 - s)))


def constant_concepts(run: Run) -> set[str]:
    """Concepts on whose clips the run's per-frame surprise is one and the same trace."""
    out = set()
    for concept, grp in run.clips.groupby("concept"):
        x = run.nll[grp.index.to_numpy()]  # (n, T)
        x = x[:, ~np.isnan(x).all(0)]  # frames scored in some clip
        if np.array_equal(np.fmax.reduce(x, 0), np.fmin.reduce(x, 0), equal_nan=True):
            out.add(concept)
    return out


def _could_fail(ctrl: Control, expected: str, set_ids: np.ndarray, constant: bool,
                balance: pd.DataFrame | None) -> bool | None:
    if expected == "none":
        return None
    if constant:
        return False
    if expected == "chance" and ctrl.invariant_to and balance is not None:
        reached = balance.set_index("set_id")[ctrl.invariant_to].reindex(set_ids)
        if reached.notna().all() and reached.astype(bool).all():
            return False
    return True


def _cells(ctrl: Control, run: Run, n_boot: int, balance: pd.DataFrame | None) -> list[dict]:
    sets = set_table(run)
    cond, carries = set_conditions(sets)
    sets = sets.assign(condition=cond, carries=carries)
    constant = constant_concepts(run)
    # a random network speaks for models of its own class only (voe.controls.confound)
    scope = str(run.meta.get("model", {}).get("class", "")) if ctrl.family == "random-net" else ""
    groups = [(c, None, g[g["carries"]]) for c, g in sets.groupby("concept", sort=True)]
    groups += [(c, k, g) for (c, k), g in sets.groupby(["concept", "condition"], sort=True)]
    rows = []
    for concept, cond_, g in groups:
        acc = g["accuracy"].to_numpy()
        lo, hi = bootstrap_ci(acc, n_boot=n_boot)
        h = g["halves"].to_numpy(dtype=np.float64)  # (n_sets,) NaN for pairs and unchecked quadruplets
        spliced = len(g) > 0 and bool((g["set_kind"] == "quadruplet").all()) and not np.isnan(h).any()
        carries_ = bool(g["carries"].all()) if len(g) else False
        expected = ctrl.expectation(concept, cond_)
        if cond_ and expected == "none" and carries_ and ctrl.expectation(concept) in INHERITED:
            expected = ctrl.expectation(concept)
        rows.append({"control": ctrl.name, "family": ctrl.family, "scope": scope, "concept": concept,
                     "condition": cond_ or "all", "carries_verdict": carries_,
                     "n_sets": len(acc), "accuracy": accuracy(acc), "ci_low": lo, "ci_high": hi,
                     "p_value": permutation_pvalue(acc), "p_two_sided": two_sided_pvalue(acc),
                     "_halves": halves_cells(g, n_boot, 0),
                     # the statistic that carries a verdict here (voe.controls.confound.off_chance)
                     "verdict_stat": "halves" if spliced else "sum",
                     "halves_p_two_sided": two_sided_pvalue(h) if spliced else float("nan"),
                     "expected": expected,
                     "could_fail": _could_fail(ctrl, expected, g["set_id"].to_numpy(), concept in constant,
                                               balance)})
    return rows


def specificity_matrix(controls: Sequence[Control], runs: Sequence[Run], n_boot: int = 10_000,
                       balance: pd.DataFrame | None = None) -> pd.DataFrame:
    """Rows per control x concept (``condition == 'all'``) and x condition, with verdicts.

    ``runs[i]`` must be the run of ``controls[i]``; ``balance`` is ``probe_runs.set_balance``
    of the probe set (without it, no cell is classed as fixed by balance). p-values are
    Holm-corrected across the concept rows of a control (and separately across its condition rows).
    """
    if len(controls) != len(runs):
        raise ValueError("one run per control")
    rows: list[dict] = []
    for ctrl, run in zip(controls, runs, strict=True):
        cells = _cells(ctrl, run, n_boot, balance)
        for part in ([r for r in cells if r["condition"] == "all"], [r for r in cells if r["condition"] != "all"]):
            if not part:
                continue
            judge(part)  # a control faces the rule a model faces, the halves included
            for r in part:
                r["as_declared"] = outcome_ok(r["expected"], r["verdict"], r["ci_low"], r["ci_high"])
        rows += cells
    return pd.DataFrame(rows)


def mismatches(matrix: pd.DataFrame) -> pd.DataFrame:
    """Cells whose outcome differs from the declaration."""
    return matrix[matrix["as_declared"].eq(False)]
