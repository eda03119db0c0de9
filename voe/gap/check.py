"""The last stage: every accepted effect must earn its place and be established, then the test
episodes say how much better the recordings are predicted, and the verdict is written.

Why: the greedy search can accept an empty effect (in one run a ``quadratic_drag`` with c = 0
took the credit for refitting a correct ``rolling_resistance``). So each accepted effect is
removed in turn and the rest refitted without it; the selection error must rise by more than the
threshold of the round that accepted it, or it goes. Each remaining effect's parameters get 95 %
bootstrap intervals over fitting windows, and an effect whose interval contains its nominal
value (zero strength, the scene's own coefficient) is not established and not reported. Only
then are the test episodes, untouched so far, simulated.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.folds import as_sum, without
from voe.gap.search import window_gain
from voe.gap.stages import GapConfig, Location, Problem, Search, context_for, fit_windows
from voe.gap.uncertainty import established, intervals
from voe.gap.verify import Verification, verify


@dataclass(frozen=True)
class Checked:
    """The model that survived, why others were dropped, and the test figures."""

    model: FitResult | None
    keys: tuple[str, ...]
    lower: np.ndarray  # (P,) 95 % interval ends of the model's parameters
    upper: np.ndarray
    dropped: tuple[dict, ...]  # {"effect", "reason"} per dropped effect
    verification: Verification
    test_note: str
    nominal: np.ndarray  # (P,) the model's parameters at which nothing changes (NaN: no such value)


def check_step(p: Problem, loc: Location, s: Search, config: GapConfig, seed: int) -> Checked:
    """Prune, bound and test the search's model."""
    model, keys = s.result.model, list(s.result.keys)
    thresholds = [r.threshold for r in s.result.rounds if r.winner]
    dropped: list[dict] = []
    fit_ids = p.split.fit
    ctx = context_for(p.scene, [p.episodes[i] for i in fit_ids])
    lo = hi = np.zeros(0)
    for _ in range(2 * len(keys) + 1):
        if model is None:
            break
        if len(keys) > 1:  # earn its place: refit without each part
            rises = []
            for k in range(len(keys)):
                eff, starts = without(model, k)
                red = s.fitter.refit(eff, starts, s.fitter.config.refine_nfev)
                rises.append((window_gain(red.window_sse, model.window_sse), k, red))
            rise, k, red = min(rises, key=lambda r: r[0] - thresholds[r[1]])
            if rise <= thresholds[k]:
                dropped.append({"effect": keys[k], "reason": f"without it the selection error rises {100 * rise:.1f} %, "
                                                             f"not more than the threshold {100 * thresholds[k]:.1f} %"})
                model, keys, thresholds = as_sum(red), keys[:k] + keys[k + 1:], thresholds[:k] + thresholds[k + 1:]
                continue
        lo, hi = intervals(p.shooter, p.sigma, fit_windows(p, fit_ids, config), model.effect, model.params,
                           ctx, config.fit.f_scale, seed)
        ok = established(model.effect, lo, hi, ctx)
        if all(ok):
            break
        k = ok.index(False)
        i = model.effect.split(np.arange(model.params.size))[k].astype(int)  # part k's parameter indices
        dropped.append({"effect": keys[k], "reason": "its 95 % interval contains the nominal value (not established)",
                        "params": model.params[i].tolist(), "interval95": np.c_[lo[i], hi[i]].tolist()})
        eff, starts = without(model, k)
        model = None if eff is None else as_sum(s.fitter.refit(eff, starts, s.fitter.config.refine_nfev))
        keys, thresholds = keys[:k] + keys[k + 1:], thresholds[:k] + thresholds[k + 1:]
    if model is None:
        lo = hi = np.zeros(0)
    ver, note = _test(p, model, config, loc.z_threshold)
    nominal = model.effect.nominal(ctx) if model is not None else np.zeros(0)
    return Checked(model, tuple(keys), lo, hi, tuple(dropped), ver, note, nominal)


def _test(p: Problem, model: FitResult | None, config: GapConfig, z_thr: float) -> tuple[Verification, str]:
    """Simulate the test episodes (each fold's own episode and parameters in cross-validation)."""
    effect = model.effect if model is not None else None
    if p.split.cross_validated:
        pairs = [(w, None if model is None else model.fold_params[k])
                 for k, (_, sel) in enumerate(p.split.folds) for w in fit_windows(p, sel, config)]
        note = "cross-validated over episodes (no untouched test split)"
    else:
        pairs = [(w, None if model is None else model.params) for w in fit_windows(p, p.split.test, config)]
        note = f"test episodes {[p.episodes[i].id for i in p.split.test]}"
    return verify(p.shooter, pairs, effect, p.sigma, z_thr), note


def effect_dicts(c: Checked, p: Problem) -> list[dict]:
    """One dict per reported effect: parameters with 95 % intervals and nominal values, units,
    bodies, when it acts."""
    model, lo, hi, keys = c.model, c.lower, c.upper, c.keys
    if model is None:
        return []
    es = EffectSum(model.effect.parts)
    out, i = [], 0
    for e, v in zip(es.parts, es.split(model.params), strict=True):
        n = e.n_params
        out.append({"name": e.name, "key": keys[len(out)] if len(out) < len(keys) else e.name,
                    "params": {k: float(x) for k, x in zip(e.param_names, v, strict=True)},
                    "interval95": {k: [float(lo[i + j]), float(hi[i + j])] for j, k in enumerate(e.param_names)},
                    "nominal": {k: (None if np.isnan(c.nominal[i + j]) else float(c.nominal[i + j]))
                                for j, k in enumerate(e.param_names)},
                    "units": dict(zip(e.param_names, e.units, strict=True)),
                    "bodies": list(e.bodies) if e.bodies else p.scene.names, "acts": e.acts, "summary": e.summary})
        i += n
    return out
