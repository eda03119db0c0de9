"""The stress test: a classifier that sees one frame (or one step of change) at a time.

Why: hand-written knowledge-free scorers only find the cues someone thought of. In the spirit of
"train on the test set" (2025), a logistic regression is trained on single frames (or single
steps ``|x_t - x_{t-1}|``), each labelled with its clip's class (impossible = 1), and
cross-validated over matched sets: the sets it scores were held out of its training, whole. A
clip's score is the mean of its frames' log-odds. Whatever it finds, a single frame or a single
step gives away, and no model should be credited with a concept for it.

On an F-balanced set (the impossible clips hold exactly the possible clips' frames) the frame
classifier ties by construction: the same classifier (one fold holds out the whole set) gives
identical frames identical scores, so both sides sum the same multiset. Identical inputs are
scored once (``np.unique``), so the scores are bit-identical too. The step classifier ties on
M-balanced sets for the same reason. It never sees a whole clip: a supervised model of whole
clips could learn the concept itself.

The regression is plain L2-regularised logistic regression fitted with scipy's L-BFGS (scipy is
already a dependency; no scikit-learn needed), on block-averaged inputs standardised on the
training folds.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize

from voe.controls.statistics import StatTraces, concept_chunks
from voe.io.probeset import ProbeSet

#: Inputs are block-averaged down to at most this many pixels a side.
GRID = 16
#: L2 penalty of the regression (on standardised inputs).
L2 = 1e-2
#: Cross-validation folds over matched sets (fewer when there are fewer sets).
FOLDS = 5


def _downsample(x: np.ndarray) -> np.ndarray:
    """``(n, H, W)`` -> ``(n, g*g)`` block means, ``g = min(GRID, H)``."""
    n, H, W = x.shape
    g = min(GRID, H)
    b = H // g
    x = x[:, : g * b, : g * b].astype(np.float64)
    return x.reshape(n, g, b, g, b).mean(axis=(2, 4)).reshape(n, g * g)


def fit_logistic(X: np.ndarray, n_pos: np.ndarray, n_neg: np.ndarray,
                 l2: float = L2) -> tuple[np.ndarray, float, np.ndarray, np.ndarray]:
    """Fit ``p(y=1|x)`` on distinct inputs ``X (u, d)`` seen ``n_pos`` times labelled 1 and
    ``n_neg`` times labelled 0 (the same as one row per occurrence, but cheaper); inputs are
    standardised with the occurrence-weighted mean and scale. Returns ``(w, b, mean, scale)``."""
    n = n_pos + n_neg  # (u,)
    N = float(n.sum())
    mu = (n[:, None] * X).sum(0) / N
    sd = np.sqrt((n[:, None] * (X - mu) ** 2).sum(0) / N) + 1e-6
    Z = (X - mu) / sd  # (u, d)
    d = Z.shape[1]

    def loss(theta: np.ndarray) -> tuple[float, np.ndarray]:
        w, b = theta[:d], theta[d]
        z = Z @ w + b  # (u,)
        lz = np.logaddexp(0.0, z)  # log(1 + e^z), stable
        val = float((n * lz - n_pos * z).sum() / N + 0.5 * l2 * w @ w)
        g = (n * np.exp(z - lz) - n_pos) / N  # (u,) d loss / d z
        return val, np.concatenate([Z.T @ g + l2 * w, [g.sum()]])

    res = minimize(loss, np.zeros(d + 1), jac=True, method="L-BFGS-B", options={"maxiter": 200})
    return res.x[:d], float(res.x[d]), mu, sd


def folds(set_ids: np.ndarray, k: int = FOLDS) -> np.ndarray:
    """Fold of each row: matched sets (sorted by id) dealt round-robin into ``min(k, n_sets)`` folds."""
    uniq = np.unique(set_ids)
    fold_of = {s: i % min(k, len(uniq)) for i, s in enumerate(uniq)}
    return np.array([fold_of[s] for s in set_ids])


def _inputs(frames: np.ndarray, kind: str) -> np.ndarray:
    """``(B, T, H, W)`` uint8 -> per-frame inputs ``(B, T, H, W)`` uint8 (step 0 is all zero)."""
    if kind == "frame":
        return frames
    x = frames.astype(np.int16)
    out = np.zeros_like(frames)
    out[:, 1:] = np.abs(x[:, 1:] - x[:, :-1]).astype(np.uint8)
    return out


def stress_traces(ps: ProbeSet, kind: str = "frame") -> StatTraces:
    """Cross-validated per-frame log-odds of "impossible" for every clip (``kind``: frame|step).

    Frame 0 of the step classifier has no step and is NaN (not scored, in every clip).
    """
    if kind not in ("frame", "step"):
        raise ValueError(f"stress test kind must be 'frame' or 'step', not {kind!r}")
    out: np.ndarray | None = None
    n_folds: dict[str, int] = {}
    for concept, rows, arrays in concept_chunks(ps):
        idx = ps.index.iloc[rows]
        B, T, H, W = arrays["frames"].shape
        x = np.ascontiguousarray(_inputs(arrays["frames"], kind).reshape(B * T, H * W))  # (B*T, H*W)
        rows_as_bytes = x.view(np.dtype((np.void, H * W))).ravel()  # (B*T,) one opaque item per input
        _, first, inv = np.unique(rows_as_bytes, return_index=True, return_inverse=True)
        uniq = x[first]  # (U, H*W) identical inputs are scored once
        inv = inv.reshape(B, T)
        feats = _downsample(uniq.reshape(-1, H, W))  # (U, g*g)
        y = (idx["role"].to_numpy() == "impossible").astype(np.float64)  # (B,)
        fold = folds(idx["set_id"].to_numpy())
        first = 1 if kind == "step" else 0
        tr = np.zeros((B, T))
        n_folds[concept] = int(fold.max()) + 1
        for f in range(n_folds[concept]):
            test = fold == f
            if test.all():  # one set only: nothing to learn from, every clip ties
                continue
            u_train = inv[~test, first:].ravel()  # (n_train_frames,) distinct-input ids
            y_train = np.repeat(y[~test], T - first)
            n_pos = np.bincount(u_train, weights=y_train, minlength=len(feats))
            n_neg = np.bincount(u_train, weights=1 - y_train, minlength=len(feats))
            seen = (n_pos + n_neg) > 0
            w, b, mu, sd = fit_logistic(feats[seen], n_pos[seen], n_neg[seen])
            score_u = ((feats - mu) / sd) @ w + b  # (U,) one score per distinct input
            tr[test] = score_u[inv[test]]
        if kind == "step":
            tr[:, 0] = np.nan
        if out is None:
            out = np.full((len(ps), T), np.nan)
        out[rows] = tr
    assert out is not None
    return StatTraces(f"stress-{kind}", out, {"invariant_to": "F" if kind == "frame" else "M",
                                              "folds": n_folds})
