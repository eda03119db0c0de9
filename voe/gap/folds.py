"""One fitter per fold: the search sees a single interface for a three-way split (one fold) and
for cross-validation over episodes (one fold per held-out episode).

Why: the greedy search, the null and the checks of each accepted effect all ask the same three
things (fit a candidate on top of the current model, refine it, score it on selection windows).
Behind this facade each fold fits on its own fitting episodes, with a context built from them
alone, and is scored on its own selection windows; a result keeps every fold's parameters, and
its per-window errors are the folds' concatenated.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from voe.gap.effects.base import Effect, EffectSum
from voe.gap.fit import FitResult, Fitter, extend
from voe.gap.shooting import Shooter, Window


class FoldedFitter:
    """Fits and scores effects over ``folds`` (each a ``Fitter`` with train and selection windows)."""

    def __init__(self, folds: list[Fitter]) -> None:
        self.folds = folds
        self.shooter: Shooter = folds[0].shooter
        self.config = folds[0].config

    @property
    def test(self) -> list[Window]:
        """Every fold's selection windows, in fold order."""
        return [w for f in self.folds for w in f.test]

    def heldout_sse(self, effect: Effect | None = None, fold_params: tuple[np.ndarray, ...] | None = None) -> np.ndarray:
        """(W,) selection SSE per window, each fold with its own parameters."""
        return np.concatenate([f.heldout_sse(effect, None if fold_params is None else fold_params[k])
                               for k, f in enumerate(self.folds)])

    def _combine(self, parts: list[FitResult]) -> FitResult:
        fold_params = tuple(r.params for r in parts)
        sse = np.concatenate([r.window_sse for r in parts])
        n = sum(f._n_test for f in self.folds)
        return FitResult(parts[0].effect, np.median(np.stack(fold_params), axis=0), float(sum(r.train_cost for r in parts)),
                         float(np.sqrt(np.sum(sse) / max(n, 1))), sse, fold_params, all(r.train_full for r in parts),
                         any(r.grid_end for r in parts))

    def fit_candidate(self, current: FitResult | None, cand: Effect) -> FitResult:
        """``current + cand`` fitted in every fold from that fold's current parameters."""
        out = []
        for k, f in enumerate(self.folds):
            cur_e = current.effect if current is not None else None
            cur_p = current.fold_params[k] if current is not None else np.zeros(0)
            effect, starts = extend(cur_e, cur_p, cand, f.ctx)
            out.append(f.fit(effect, starts))
        return self._combine(out)

    def refit(self, effect: Effect, fold_starts: tuple[np.ndarray, ...], max_nfev: int | None = None) -> FitResult:
        """Fit ``effect`` in every fold from that fold's start."""
        return self._combine([f.fit(effect, [s], max_nfev) for f, s in zip(self.folds, fold_starts, strict=True)])

    def refine(self, res: FitResult) -> FitResult:
        """The refine step: a longer fit from the result's own parameters."""
        return self.refit(res.effect, res.fold_params, self.config.refine_nfev)

    def unfocused(self) -> FoldedFitter:
        """Every fold's ``Fitter.unfocused``: fits on the training windows only."""
        return FoldedFitter([f.unfocused() for f in self.folds])

    def residuals(self, effect: Effect | None, fold_params: tuple[np.ndarray, ...] | None) -> list[np.ndarray]:
        """Selection-window residuals (n, B, 3) per window, in ``test`` order."""
        return [r for k, f in enumerate(self.folds)
                for r in self.shooter.residuals(f.test, effect, None if fold_params is None else fold_params[k])]


def without(res: FitResult, k: int) -> tuple[Effect | None, tuple[np.ndarray, ...]]:
    """``res``'s effect with part ``k`` removed, and every fold's parameters for what is left."""
    parts = list(res.effect.parts)
    if len(parts) == 1:
        return None, tuple(np.zeros(0) for _ in res.fold_params)
    keep = [i for i in range(len(parts)) if i != k]
    eff = EffectSum(tuple(parts[i] for i in keep))
    starts = []
    for p in res.fold_params:
        split = EffectSum(tuple(parts)).split(p)
        starts.append(np.concatenate([split[i] for i in keep]))
    return eff, tuple(starts)


def as_sum(res: FitResult) -> FitResult:
    """``res`` with its effect wrapped as an ``EffectSum`` (the finder's reporting form)."""
    if isinstance(res.effect, EffectSum):
        return res
    return replace(res, effect=EffectSum(res.effect.parts))
