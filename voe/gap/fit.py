"""Fit one candidate effect's parameters on training windows and score it on held-out windows.

Why: every hypothesis is judged the same way. Parameters are fitted with
``scipy.optimize.least_squares`` on multiple-shooting residuals standardised by the expected
residual of a correct model (so noise, not metres, sets the scale) with a soft-L1 loss that keeps
a few chaotic windows from dominating. The verdict on a hypothesis is its held-out RMSE, never
its training cost, so a flexible effect gains nothing by overfitting.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from voe.gap.effects.base import Effect, EffectSum, FitContext
from voe.gap.shooting import Shooter, Window, rmse


@dataclass(frozen=True)
class FitConfig:
    """How hard to try. ``max_nfev`` bounds least-squares evaluations per candidate."""

    max_nfev: int = 10
    refine_nfev: int = 30
    f_scale: float = 3.0  # soft-L1 knee, in units of the expected residual


@dataclass(frozen=True)
class FitResult:
    """A fitted candidate: the effect, its parameters, and held-out RMSE after fitting."""

    effect: Effect
    params: np.ndarray
    train_cost: float
    heldout_rmse: float


class Fitter:
    """Fits effects on ``train`` windows and scores them on ``test`` windows.

    Args:
        shooter: simulates windows.
        sigma: (B, 3) noise floor.
        train, test: windows.
        ctx: problem description for starting points and scales.
    """

    def __init__(self, shooter: Shooter, sigma: np.ndarray, train: list[Window], test: list[Window],
                 ctx: FitContext, config: FitConfig | None = None) -> None:
        self.shooter, self.train, self.test, self.ctx = shooter, train, test, ctx
        self.config = config or FitConfig()
        self._weights = [1.0 / shooter.sigma_pred(w, sigma) for w in train]  # each (n, B, 3)

    def standardized(self, effect: Effect | None, params: np.ndarray | None) -> np.ndarray:
        """Training residuals divided by their expected size, flattened."""
        parts = [(self.shooter.residual(w, effect, params) * wt).reshape(-1)
                 for w, wt in zip(self.train, self._weights, strict=True)]
        out = np.concatenate(parts)
        return np.nan_to_num(out, nan=1e6, posinf=1e6, neginf=-1e6)

    def heldout(self, effect: Effect | None, params: np.ndarray | None) -> float:
        """Held-out RMSE in metres (x, y and angle times sqrt(I/m))."""
        return rmse([self.shooter.residual(w, effect, params) for w in self.test])

    def cost(self, effect: Effect | None, params: np.ndarray | None) -> float:
        z = self.standardized(effect, params)
        fs = self.config.f_scale
        return float(np.sum(2 * fs**2 * (np.sqrt(1 + (z / fs) ** 2) - 1)))

    def fit(self, effect: Effect, starts: list[np.ndarray] | None = None, max_nfev: int | None = None) -> FitResult:
        """Fit ``effect`` from the most promising of ``starts`` (default: the effect's own)."""
        if effect.n_params == 0:
            return FitResult(effect, np.zeros(0), self.cost(effect, np.zeros(0)), self.heldout(effect, np.zeros(0)))
        lo, hi = effect.bounds(self.ctx)
        scale = effect.scale(self.ctx)
        starts = list(starts) if starts is not None else effect.starts(self.ctx)
        starts = [np.clip(s, lo + 1e-12 * scale, hi - 1e-12 * scale) for s in starts]
        if len(starts) > 1:  # pick the most promising start by training cost on a third of the windows
            sub = Fitter.__new__(Fitter)
            sub.__dict__.update(self.__dict__, train=self.train[::3], _weights=self._weights[::3])
            starts = [min(starts, key=lambda s: sub.cost(effect, s))]
        res = least_squares(
            lambda p: self.standardized(effect, p), starts[0], bounds=(lo, hi), x_scale=scale,
            diff_step=0.05 * scale / np.maximum(1.0, np.abs(starts[0])), loss="soft_l1",
            f_scale=self.config.f_scale, max_nfev=max_nfev or self.config.max_nfev, method="trf",
        )
        return FitResult(effect, res.x, float(2 * res.cost), self.heldout(effect, res.x))


def extend(current: Effect | None, params: np.ndarray, cand: Effect, ctx: FitContext) -> tuple[Effect, list[np.ndarray]]:
    """``current + cand`` and its starting points (current parameters kept, cand's starts added)."""
    if current is None:
        return cand, cand.starts(ctx)
    combo = EffectSum(current.parts + cand.parts)
    return combo, [np.concatenate([params, s]) for s in cand.starts(ctx)]
