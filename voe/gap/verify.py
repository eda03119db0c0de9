"""Verify a fitted model on held-out episodes and say in plain English what was found.

Why: a fit is only believable on data it has not seen. Held-out windows are re-simulated with and
without the accepted effects; RMSE before and after, and the share of windows whose standardised
residual still exceeds the located threshold, say whether what is left looks like noise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.shooting import Shooter, Window, position_rmse, rmse, window_score


@dataclass(frozen=True)
class Verification:
    """Held-out numbers before/after. RMSE in metres; ``flagged_*`` are window fractions."""

    rmse_before: float
    rmse_after: float
    position_rmse_before: float
    position_rmse_after: float
    window_median_before: float
    window_median_after: float
    median_z_before: float
    median_z_after: float
    flagged_before: float
    flagged_after: float
    looks_like_noise: bool


def verify(shooter: Shooter, windows: list[Window], effect: Effect | None, params: np.ndarray,
           sigma: np.ndarray, z_thr: float) -> Verification:
    """Re-simulate ``windows`` with and without ``effect``."""
    before = [shooter.residual(w, None, None) for w in windows]
    after = [shooter.residual(w, effect, params) for w in windows] if effect is not None else before
    sp = [shooter.sigma_pred(w, sigma) for w in windows]
    zb = np.array([np.sqrt(np.mean((r / s)[1:] ** 2, axis=0)).max() for r, s in zip(before, sp, strict=True)])
    za = np.array([np.sqrt(np.mean((r / s)[1:] ** 2, axis=0)).max() for r, s in zip(after, sp, strict=True)])
    flagged_after = float(np.mean(za > z_thr))
    return Verification(rmse(before), rmse(after), position_rmse(before), position_rmse(after),
                        window_score(before), window_score(after),
                        float(np.median(zb)), float(np.median(za)), float(np.mean(zb > z_thr)), flagged_after,
                        bool(flagged_after <= 0.1))


def explain(effects: list[dict], groups: list[list[str]], located: list[dict], ver: Verification,
            threshold: float, sigma: np.ndarray, holdout: list[int]) -> str:
    """A short paragraph with the numbers that matter."""
    noise_mm = 1e3 * float(np.median(sigma[:, :2]))
    if not effects:
        text = (f"The recordings agree with the nominal simulation: no candidate effect cut the held-out error by "
                f"more than the null threshold of {100 * threshold:.1f} % (noise floor about {noise_mm:.3g} mm).")
        if located:
            text += (f" {len(located)} stretch(es) still depart from the model (largest z = "
                     f"{max(x['z'] for x in located):.1f}), but none of the library's effects explains them.")
        return text
    parts = []
    for e in effects:
        params = ", ".join(f"{k} = {v:.3g}" for k, v in e["params"].items())
        parts.append(f"{e['summary']}: {e['name']} ({params}) was missing")
    drop = 100 * (1 - ver.rmse_after / ver.rmse_before) if ver.rmse_before > 0 else 0.0
    text = "; ".join(parts) + (
        f". Adding {'them' if len(effects) > 1 else 'it'} cuts held-out error (RMSE of x, y and angle x sqrt(I/m)) on episodes {holdout} from "
        f"{ver.rmse_before:.3g} m to {ver.rmse_after:.3g} m ({drop:.0f} % less; position only "
        f"{ver.position_rmse_before:.3g} m to {ver.position_rmse_after:.3g} m).")
    if located:
        ctxs = sorted({x["context"] for x in located})
        text += f" The mismatch was located in {len(located)} stretch(es), context: {', '.join(ctxs)}."
    for g in groups:
        if len(g) > 1:
            text += f" The data cannot tell apart {' and '.join(g)} (held-out fits within 10 %); {g[0]} is named first."
    text += (" The remaining residuals look like noise." if ver.looks_like_noise else
             f" {100 * ver.flagged_after:.0f} % of held-out windows still exceed the noise threshold.")
    return text
