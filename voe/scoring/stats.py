"""Statistics over matched sets: bootstrap CIs, a sign-flip permutation test and Holm correction.

Why matched sets are the unit: the clips of one set share everything but the violation, so they
are not independent observations; resampling or permuting clips would overstate confidence.
"""

from __future__ import annotations

import itertools

import numpy as np

#: Sets up to this number are tested exactly (2**n sign patterns); above it by Monte Carlo.
EXACT_MAX_SETS = 16


def bootstrap_ci(values: np.ndarray, n_boot: int = 10_000, level: float = 0.95,
                 seed: int = 0) -> tuple[float, float]:
    """Percentile bootstrap CI of the mean of per-set ``values`` (resampling sets, seeded).

    Returns ``(nan, nan)`` for no values.
    """
    v = np.asarray(values, dtype=np.float64)
    if not v.size:
        return float("nan"), float("nan")
    rng = np.random.default_rng(seed)
    means = v[rng.integers(0, v.size, size=(n_boot, v.size))].mean(axis=1)  # (n_boot,)
    alpha = (1.0 - level) / 2.0
    lo, hi = np.quantile(means, [alpha, 1.0 - alpha])
    return float(lo), float(hi)


def permutation_pvalue(set_scores: np.ndarray, n_perm: int = 10_000, seed: int = 0) -> float:
    """One-sided p-value that matched-set accuracy exceeds chance.

    Under the null hypothesis the model cannot tell which side of a set is impossible, so
    swapping the labels within a set (a score ``s`` becomes ``1 - s``) is as likely as not. The
    statistic is the mean score; ``p = P(null mean >= observed)``. Exact enumeration of all
    ``2**n`` sign patterns for ``n <= EXACT_MAX_SETS`` sets, else ``n_perm`` seeded random flips
    with the ``(1 + k) / (1 + n_perm)`` correction. Returns NaN for no sets.
    """
    s = np.asarray(set_scores, dtype=np.float64)
    if not s.size:
        return float("nan")
    centred = s - 0.5  # (n,) a flip negates it
    observed = centred.sum()
    eps = 1e-12 * max(1.0, float(np.abs(centred).sum()))
    if s.size <= EXACT_MAX_SETS:
        signs = np.array(list(itertools.product((1.0, -1.0), repeat=s.size)))  # (2**n, n)
        null = signs @ centred
        return float(np.mean(null >= observed - eps))
    rng = np.random.default_rng(seed)
    signs = rng.choice((1.0, -1.0), size=(n_perm, s.size))  # (n_perm, n)
    k = int(np.sum(signs @ centred >= observed - eps))
    return (1.0 + k) / (1.0 + n_perm)


def holm(pvalues: np.ndarray) -> np.ndarray:
    """Holm step-down adjusted p-values (family-wise error control); NaNs are left out and kept."""
    p = np.asarray(pvalues, dtype=np.float64)
    out = np.full(p.shape, np.nan)
    ok = np.flatnonzero(~np.isnan(p))
    m = ok.size
    if not m:
        return out
    order = ok[np.argsort(p[ok], kind="stable")]
    adj = np.minimum(1.0, (m - np.arange(m)) * p[order])  # (m,) (m - i) * p_(i)
    out[order] = np.maximum.accumulate(adj)
    return out
