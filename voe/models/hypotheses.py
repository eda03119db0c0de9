"""The oracle's elasticity hypotheses: refining the simulated grid, and the Bayesian mixture.

Why a refinement: the oracle simulates a grid of elasticities (0.05 apart), but one impact
moves what follows by several cells of the observation grid between two grid points (a rebound
differs by about 0.3 units/s, and an object hidden for 0.4 s comes back about 0.1 units apart).
A mixture whose neighbouring hypotheses are far apart against the noise they are scored with is
a comb, not an average over elasticity: a clip near a grid point costs little, one between two
costs several nats more, and luck decides comparisons. So between each two neighbours the
predictions are interpolated (what one impact does to the state is smooth in the elasticity),
with as many points as it takes for neighbours to differ by at most ``statelik.RETURN_FLOOR``
(half a cell, the smallest noise a returning object is scored with) on every frame that is
observed. With neighbours one sigma apart, the sum of Gaussians is flat to about 1e-8 of the
integral it stands for. The number of points is chosen per clip and per grid interval, from
the clip's own predictions alone, so a clip's surprise never depends on its batch.

Each hypothesis carries the prior weight of the span of elasticity it stands for, so the prior
stays uniform in elasticity whatever the refinement.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.special import logsumexp


def interval_counts(pred: np.ndarray, scored: np.ndarray, feats: list[int], spacing: np.ndarray,
                    angle: int, k_min: int, k_max: int) -> np.ndarray:
    """Hypotheses per grid interval so that neighbours differ by at most ``spacing``.

    Args:
        pred: ``(H, T, K, F)`` predictions of one clip on the simulated grid (NaN: unknown slot).
        scored: ``(T, K)`` bool, entries compared with an observation.
        feats: feature indices of ``spacing``; spacing: ``(len(feats),)`` per feature.
        angle: index of the angle feature (differences taken the shorter way round).
        k_min, k_max: bounds on the count of every interval.

    Returns:
        ``(H - 1,)`` ints in ``[k_min, k_max]``.
    """
    step = _step(pred[1:], pred[:-1], angle)[:, scored][..., feats]  # (H-1, N, len(feats))
    ratio = np.nan_to_num(np.abs(step) / spacing, nan=0.0)
    need = np.ceil(ratio.max(axis=(1, 2), initial=0.0) - 1e-9)  # (H-1,)
    return np.clip(need, k_min, k_max).astype(int)


def refine(pred: np.ndarray, pvis: np.ndarray, contact: np.ndarray, counts: np.ndarray,
           elasticities: tuple[float, ...], angle: int,
           p_vis: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, ...]:
    """Put ``counts[i] - 1`` hypotheses between grid points ``i`` and ``i + 1`` of one clip.

    Args:
        pred: ``(H, T, K, F)``; pvis, contact: ``(H, T, K)`` (pvis NaN for unknown slots).
        counts: ``(H - 1,)`` from ``interval_counts``.
        elasticities: the ``H`` simulated elasticities (ascending), for the prior weights.
        angle: index of the angle feature (interpolated the shorter way round).
        p_vis: P(present) of states ``(..., F)``: an interpolated hypothesis is visible where its
            own interpolated state is, not where the nearer grid point's was.

    Returns:
        pred ``(H', T, K, F)``, pvis and contact ``(H', T, K)``, and the log prior weights
        ``(H',)`` (summing to 1 in probability), with ``H' = sum(counts) + 1``; the simulated
        points are kept as they are.
    """
    H = pred.shape[0]
    if H < 2:
        return pred, pvis, contact, np.zeros(H)
    preds, vis, hits, weights = [], [], [], []
    for i, k in enumerate(counts):
        fr = np.arange(k) / k  # (k,)
        mid = pred[i][None] + _step(pred[i + 1], pred[i], angle)[None] * fr[:, None, None, None]  # (k, T, K, F)
        v = np.where(np.isnan(pvis[i])[None], np.nan, p_vis(mid))  # (k, T, K)
        v[0] = pvis[i]
        h = np.repeat((contact[i] | contact[i + 1])[None], k, axis=0)
        h[0] = contact[i]
        preds.append(mid)
        vis.append(v)
        hits.append(h)
        weights.append(np.full(k, (elasticities[i + 1] - elasticities[i]) / k))
    preds.append(pred[-1:])
    vis.append(pvis[-1:])
    hits.append(contact[-1:])
    weights.append(weights[-1][-1:])  # the last point stands for as much as its neighbour
    w = np.concatenate(weights)
    return np.concatenate(preds), np.concatenate(vis), np.concatenate(hits), np.log(w / w.sum())


def _step(hi: np.ndarray, lo: np.ndarray, angle: int) -> np.ndarray:
    """``hi - lo`` with the angle wrapped to (-pi, pi]."""
    d = hi - lo
    d[..., angle] = (d[..., angle] + np.pi) % (2 * np.pi) - np.pi
    return d


def mixture_nll(nll: np.ndarray, log_prior: np.ndarray | None = None) -> np.ndarray:
    """Per-frame surprise ``(B, T)`` of a Bayesian mixture of hypotheses.

    Args:
        nll: ``(H, B, T)`` per-frame surprise under each hypothesis alone (frame 0 NaN).
        log_prior: ``(H,)`` log prior weights (normalised); equal weights when omitted.

    Returns:
        ``-log p(o_t | o_<t)``, where the mixture weights at t are the hypotheses' posteriors
        given frames 1..t-1; frame 0 NaN.
    """
    H = nll.shape[0]
    lp = np.full(H, -np.log(H)) if log_prior is None else np.asarray(log_prior, dtype=np.float64)
    cum = np.cumsum(np.nan_to_num(nll, nan=0.0), axis=-1)  # (H, B, T): -log p(o_1..t | h)
    log_evidence = logsumexp(lp[:, None, None] - cum, axis=0)  # (B, T): log p(o_1..t)
    out = -np.diff(log_evidence, axis=-1, prepend=0.0)
    out[:, 0] = np.nan
    return out
