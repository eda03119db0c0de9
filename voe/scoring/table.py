"""Tables per model x concept (and x condition), computed from stored runs only.

Why here and not in ``report``: the numbers in a report, a notebook and a test must come from the
same code; the report only lays them out.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from voe.errors import VoeError
from voe.scoring.halves import VARIANTS, cached_sides, quadruplet_halves, splice_sides
from voe.scoring.metrics import TIE_RTOL, accuracy, auroc, score_set, tie_atol
from voe.scoring.runs import Run
from voe.scoring.stats import bootstrap_ci, holm, permutation_pvalue
from voe.scoring.verdict import INCONCLUSIVE, set_conditions, verdict, with_halves

SUMMARY_COLUMNS = ("model", "concept", "n_sets", "accuracy", "ci_low", "ci_high", "p_value", "p_holm",
                   "verdict", "note", "relative_surprise", "pair_acc_max", "auroc", "halves", "halves_ci_low",
                   "halves_ci_high", "halves_p_holm")
SET_KEYS = ("concept", "set_id", "set_kind", "visible_violation", "n_distractors")
#: Set-level columns carried over when a probe set has them (``voe.scoring.verdict.set_conditions``).
OPTIONAL_SET_KEYS = ("condition", "carries_verdict", "confounded")


def holm_nan(p: np.ndarray) -> np.ndarray:
    """``holm`` over the finite entries of ``p`` (NaN stays NaN: a concept without quadruplets
    does not enter the halves' family)."""
    out = np.full(len(p), np.nan)
    ok = np.isfinite(p)
    if ok.any():
        out[ok] = holm(p[ok])
    return out


def set_table(run: Run) -> pd.DataFrame:
    """One row per matched set of ``run``: summed surprises and per-set metrics."""
    clips = run.clips
    keys_ = [*SET_KEYS, *(k for k in OPTIONAL_SET_KEYS if k in clips.columns)]
    rows = []
    atol = tie_atol(run.surprise_kind)
    sides = _sides(run) if (clips["set_kind"] == "quadruplet").any() else {}
    for keys, grp in clips.groupby(keys_, sort=True, dropna=False):
        sc = score_set(run.nll[grp.index.to_numpy()], (grp["role"] == "impossible").to_numpy(), atol)
        sid = str(dict(zip(keys_, keys, strict=True))["set_id"])
        if sid in sides and set(grp["variant"]) == set(VARIANTS):
            nll = {v: run.nll[i] for v, i in zip(grp["variant"], grp.index, strict=True)}
            half = quadruplet_halves(nll, sides[sid], atol, TIE_RTOL)
        else:  # a pair has no halves (NaN), and a quadruplet whose probe set is gone is unchecked
            half = float("nan")
        rows.append({"model": run.label, **dict(zip(keys_, keys, strict=True)), "halves": half,
                     "s_imp": sc.s_imp, "s_pos": sc.s_pos, "accuracy": sc.accuracy,
                     "accuracy_max": sc.accuracy_max, "n_frames": sc.n_frames,
                     # a ratio of sums means something only for non-negative calibrated nats
                     "relative": sc.relative if run.surprise_kind == "nll" else float("nan")})
    out = pd.DataFrame(rows)
    dup = out["set_id"].duplicated()
    if dup.any():
        from voe.errors import RunError

        raise RunError(f"{run.path}: set '{out['set_id'][dup].iloc[0]}' has clips with different "
                       "concept/kind/conditions in clips.parquet")
    return out


def _sides(run: Run) -> dict:
    """The run's probe set's splice sides (``voe.scoring.halves.splice_sides``); ``{}`` when the
    probe set cannot be opened or is not the one scored (its quadruplets then stay unchecked)."""
    from voe.io.probeset import load_probe_set

    known = cached_sides(run.manifest_sha256)  # every table of every run on a probe set: read once
    if known is not None:
        return known
    try:
        ps = load_probe_set(run.probes_path)
        if ps.manifest_sha256 != run.manifest_sha256:
            return {}
        return splice_sides(ps)
    except (OSError, ValueError, KeyError, VoeError):
        return {}


def halves_cells(sets: pd.DataFrame, n_boot: int, seed: int) -> dict[str, float] | None:
    """Halves accuracy with CI and p-value over a cell's quadruplets (``None`` if it has none;
    NaN accuracy if any of them could not be checked)."""
    q = sets[sets["set_kind"] == "quadruplet"]
    if q.empty:
        return None
    h = q["halves"].to_numpy()
    if np.isnan(h).any():
        return {"halves": float("nan"), "halves_ci_low": float("nan"), "halves_ci_high": float("nan"),
                "halves_p": float("nan")}
    lo, hi = bootstrap_ci(h, n_boot=n_boot, seed=seed)
    return {"halves": accuracy(h), "halves_ci_low": lo, "halves_ci_high": hi,
            "halves_p": permutation_pvalue(h, seed=seed)}


def halves_verdict(cell: dict | None, p_holm: float) -> tuple[str, str] | None:
    """The halves' own verdict for ``with_halves`` (``None`` without quadruplets)."""
    if cell is None:
        return None
    if np.isnan(cell["halves"]):
        return INCONCLUSIVE, "halves unchecked (probe set not found)"
    return verdict(cell["halves"], cell["halves_ci_low"], cell["halves_ci_high"], p_holm)


def judge(rows: list[dict]) -> np.ndarray:
    """Verdicts of one family of cells (a model's concepts, or a control's): Holm over the sum's
    p-values and, separately, over the halves' (``halves_cells`` under ``_halves``, removed
    here), each cell's ``p_holm``, ``verdict`` and ``note`` set by ``with_halves``.

    Returns:
        ``(len(rows),)`` Holm-adjusted halves p-values (NaN for cells without quadruplets).
    """
    adj = holm(np.array([r["p_value"] for r in rows]))
    adj_h = holm_nan(np.array([r["_halves"]["halves_p"] if r["_halves"] else np.nan for r in rows]))
    for r, p, ph in zip(rows, adj, adj_h, strict=True):
        r["p_holm"] = float(p)
        h = r.pop("_halves")
        r.update({k: (h or {}).get(k, float("nan")) for k in ("halves", "halves_ci_low", "halves_ci_high")})
        r["verdict"], r["note"] = with_halves(verdict(r["accuracy"], r["ci_low"], r["ci_high"], r["p_holm"]),
                                              halves_verdict(h, float(ph)))
    return adj_h


def _cell(sets: pd.DataFrame, n_boot: int, seed: int) -> dict[str, float]:
    s = sets["accuracy"].to_numpy()
    lo, hi = bootstrap_ci(s, n_boot=n_boot, seed=seed)
    return {"n_sets": len(s), "accuracy": accuracy(s), "ci_low": lo, "ci_high": hi}


def concept_table(runs: Sequence[Run], n_boot: int = 10_000, seed: int = 0) -> pd.DataFrame:
    """Per model x concept: accuracy with CI, p-values (raw and Holm across a model's concepts),
    verdict, relative surprise, pair accuracy on max surprise and AUROC over clips."""
    rows = []
    for run in runs:
        sets = set_table(run)
        sets = sets[set_conditions(sets)[1]]  # a perceptual condition carries no verdict
        start = len(rows)
        for concept, grp in sets.groupby("concept", sort=True):
            clips = run.clips[run.clips["set_id"].isin(grp["set_id"])]
            rows.append({"model": run.label, "concept": concept, **_cell(grp, n_boot, seed),
                         "p_value": permutation_pvalue(grp["accuracy"].to_numpy(), seed=seed),
                         "relative_surprise": float(np.nanmean(grp["relative"])) if grp["relative"].notna().any() else float("nan"),
                         "pair_acc_max": accuracy(grp["accuracy_max"].to_numpy()),
                         "auroc": auroc(clips["sum"].to_numpy(), (clips["role"] == "impossible").to_numpy(),
                                        tie_atol(run.surprise_kind))})
            rows[-1]["_halves"] = halves_cells(grp, n_boot, seed)
        for r, ph in zip(rows[start:], judge(rows[start:]), strict=True):
            r["halves_p_holm"] = float(ph)
    return pd.DataFrame(rows, columns=list(SUMMARY_COLUMNS))


def condition_table(runs: Sequence[Run], n_boot: int = 10_000, seed: int = 0) -> pd.DataFrame:
    """Per model x concept x condition (``visible``/``occluded``; ``k distractors``), plus the
    pooled ``concept == 'all'`` rows; accuracy with bootstrap CI."""
    rows = []
    for run in runs:
        sets = set_table(run)
        sets["visibility"] = set_conditions(sets)[0]  # visible / occluded / perceptual
        sets["distractors"] = sets["n_distractors"].astype(int).map(lambda k: f"{k} distractor{'' if k == 1 else 's'}")
        for kind in ("visibility", "distractors"):
            for concept, per_concept in [*sets.groupby("concept", sort=True), ("all", sets)]:
                for cond, grp in per_concept.groupby(kind, sort=True):
                    rows.append({"model": run.label, "concept": concept, "condition_kind": kind,
                                 "condition": cond, **_cell(grp, n_boot, seed)})
    return pd.DataFrame(rows)
