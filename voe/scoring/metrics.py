"""Metrics of a model on matched sets: pure functions of per-frame surprise, ties count 0.5.

Definitions (S = summed surprise; in nats for ``nll`` models, the model's own scale for ``bound``
and ``error`` models, on which every metric except relative surprise works unchanged, since
they only compare sums):

* **matched-set accuracy** (primary): a quadruplet scores 1 if ``S(AB) + S(BA) > S(A) + S(B)``,
  0.5 on a tie, 0 otherwise; a pair compares its impossible clip with its possible clip.
* **pair accuracy on max surprise**: over every (possible, impossible) pair of clips of a set,
  1 / 0.5 / 0 as the impossible clip's peak surprise is above / equal to / below the possible one's;
  averaged within the set.
* **relative surprise**: ``(S_imp - S_pos) / (S_imp + S_pos)`` per set (NaN if the denominator is
  not positive, which only happens with negative log-densities).
* **AUROC** over all clips: P(an impossible clip's total surprise > a possible clip's), ties 0.5.

Frames a model does not score (NaN) are dropped from *every* clip of a set before summing, so the
compared sums always cover the same frames. Two sums closer than ``TIE_RTOL`` (relative) or
``TIE_ATOL`` nats are a tie: a frame-only scorer on a spliced quadruplet must tie exactly, and float
rounding must not break the tie in its favour (the "null submission scores perfectly" bug of the
field). A hundredth of a nat over whole clips is a likelihood ratio of 1.01: differences that small
come from float rounding and simulator round-off (a physics model re-simulating a spliced clip's
hidden object with the other clip's shape), not from anything a model has understood.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TIE_RTOL = 1e-9
TIE_ATOL = 0.01  # nats


def tie_atol(surprise_kind: str) -> float:
    """The absolute tie tolerance: ``TIE_ATOL`` for nats; none for a bound or an error, whose scale
    is the model's own (only the relative ``TIE_RTOL`` then applies)."""
    return TIE_ATOL if surprise_kind == "nll" else 0.0


def compare(s_imp: np.ndarray | float, s_pos: np.ndarray | float, atol: float = TIE_ATOL) -> np.ndarray:
    """1 where ``s_imp > s_pos``, 0.5 on a tie (within ``TIE_RTOL`` or ``TIE_ATOL``), 0 where below."""
    a, b = np.asarray(s_imp, dtype=np.float64), np.asarray(s_pos, dtype=np.float64)
    tol = TIE_RTOL * (np.abs(a) + np.abs(b)) + atol
    return np.where(np.abs(a - b) <= tol, 0.5, np.where(a > b, 1.0, 0.0))


@dataclass(frozen=True)
class SetScore:
    """Metrics of one matched set (see the module docstring)."""

    s_imp: float
    s_pos: float
    accuracy: float
    accuracy_max: float
    relative: float
    n_frames: int  # frames scored in every clip of the set


def score_set(traces: np.ndarray, impossible: np.ndarray, atol: float = TIE_ATOL) -> SetScore:
    """Score one matched set.

    Args:
        traces: ``(n_clips, T)`` per-frame surprise, NaN where not scored.
        impossible: ``(n_clips,)`` bool, True for impossible clips (2+2 or 1+1).
        atol: absolute tie tolerance (``tie_atol(surprise_kind)``).
    """
    traces = np.asarray(traces, dtype=np.float64)
    imp = np.asarray(impossible, dtype=bool)
    if imp.all() or not imp.any():
        raise ValueError("a matched set needs both possible and impossible clips")
    mask = ~np.isnan(traces).any(axis=0)  # (T,) frames scored in every clip
    x = traces[:, mask]  # (n_clips, T')
    # Sum the per-frame difference so that identical frames cancel exactly (a + b == b + a).
    diff = float((x[imp].sum(axis=0) - x[~imp].sum(axis=0)).sum())
    s_imp, s_pos = float(x[imp].sum()), float(x[~imp].sum())
    tol = TIE_RTOL * (abs(s_imp) + abs(s_pos)) + atol
    acc = 0.5 if abs(diff) <= tol else (1.0 if diff > 0 else 0.0)
    if x.shape[1]:
        peak = x.max(axis=1)  # (n_clips,)
        acc_max = float(compare(peak[imp][:, None], peak[~imp][None, :], atol).mean())
    else:
        acc_max = 0.5
    denom = s_imp + s_pos
    rel = diff / denom if denom > 0 else float("nan")
    return SetScore(s_imp, s_pos, acc, acc_max, rel, int(mask.sum()))


def accuracy(set_scores: np.ndarray) -> float:
    """Mean of per-set scores (each 0, 0.5 or 1); NaN for no sets."""
    s = np.asarray(set_scores, dtype=np.float64)
    return float(s.mean()) if s.size else float("nan")


def relative_surprise(s_imp: np.ndarray, s_pos: np.ndarray) -> np.ndarray:
    """Per set ``(S_imp - S_pos) / (S_imp + S_pos)``; NaN where the denominator is not positive."""
    a, b = np.asarray(s_imp, dtype=np.float64), np.asarray(s_pos, dtype=np.float64)
    d = a + b
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(d > 0, (a - b) / np.where(d > 0, d, 1.0), np.nan)


def auroc(scores: np.ndarray, impossible: np.ndarray, atol: float = TIE_ATOL) -> float:
    """Area under the ROC curve of ``scores`` for the label ``impossible``; ties count 0.5.

    Computed as the Mann-Whitney probability over every (impossible, possible) pair of clips.
    """
    s = np.asarray(scores, dtype=np.float64)
    y = np.asarray(impossible, dtype=bool)
    pos, neg = s[y], s[~y]
    if not pos.size or not neg.size:
        return float("nan")
    return float(compare(pos[:, None], neg[None, :], atol).mean())  # (n_imp, n_pos) -> scalar
