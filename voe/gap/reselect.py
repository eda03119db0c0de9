"""Re-selection: once the search has ended with several effects, each part is asked again
whether another candidate of its own round explains the data better with the other parts in.

Why: a round picks its winner on top of the model of the rounds before it, while the effects
of later rounds are still unmodelled, and a flexible candidate can absorb part of an effect
that is not yet in. Development case 9028132 (a constant acceleration (0.257, -0.864) and a spin
damping): round 1 picked the four-parameter ``spring_anchor`` (selection gain 65.8 %) over
``constant_acceleration`` (54.9 %), the spring's anchor bending its pull toward what the
damping does; round 2 added ``angular_damping``. With the damping in, the constant in the
spring's place gains 70.8 % over the spring model on the selection windows (its 5 % bootstrap
quantile 54.1 %), at (0.235, -0.901). A greedy search never revisits a round; this asks each
round's question again, once, with the answer of the later rounds known (a backward step of
stepwise selection).

Only candidates that passed their round alone (gain above that round's null threshold) are
asked, and one takes the place only if it gains more than that threshold again over the whole
model, with a positive bootstrap lower bound: the same evidence the round demanded of its
winner, now against the winner itself.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter
from voe.gap.search import Round, gain_lower_bound, window_gain


def swapped(fitter: FoldedFitter, model: FitResult, k: int, cand: FitResult) -> FitResult:
    """``model`` with part ``k`` replaced by the last part of ``cand`` (a round's candidate fit),
    refined; each fold starts from the model's other parts and the candidate's own parameters."""
    parts = list(model.effect.parts)
    part = cand.effect.parts[-1]
    eff = EffectSum(tuple(parts[:k] + [part] + parts[k + 1:]))
    starts = []
    for fp, cp in zip(model.fold_params, cand.fold_params, strict=True):
        mine = EffectSum(tuple(parts)).split(fp)  # the model's parameters per part
        own = EffectSum(cand.effect.parts).split(cp)[-1]
        starts.append(np.concatenate(mine[:k] + [own] + mine[k + 1:]))
    return fitter.refit(eff, tuple(starts), fitter.config.refine_nfev)


def reselect(fitter: FoldedFitter, model: FitResult | None, keys: list[str], rounds: list[Round],
             q: float, fixed: set[str] = frozenset()) -> tuple[FitResult | None, list[str], bool]:
    """Ask each part of a model of two or more parts again (see the module). Returns the model,
    its keys (in part order) and whether anything changed; ``rounds`` is updated in place (the
    round of a replaced part names its new winner and says why).

    ``fixed``: parts not asked again, those a pair step accepted (together, because no single
    candidate passed their round on its own; a candidate that did was a trial the next round
    refused, ``voe.gap.greedy.Trial``, and is not brought back here)."""
    if model is None or len(keys) < 2:
        return model, keys, False
    changed = False
    for k, key in enumerate(list(keys)):
        at = next((i for i, r in enumerate(rounds) if r.winner == key), None)
        rnd = rounds[at] if at is not None else None
        if rnd is None or rnd.threshold is None or key in fixed:
            continue
        alts = sorted((c for c, g in rnd.gains.items()
                       if c not in keys and c in rnd.results and np.isfinite(g) and g > rnd.threshold),
                      key=lambda c: -rnd.gains[c])
        best: tuple[float, float, str, FitResult] | None = None
        for c in alts:
            res = swapped(fitter, model, k, rnd.results[c])
            g = window_gain(model.window_sse, res.window_sse)
            lo = gain_lower_bound(model.window_sse, res.window_sse, q=q)
            if g > rnd.threshold and lo > 0 and (best is None or g > best[0]):
                best = (g, lo, c, res)
        if best is None:
            continue
        g, lo, c, res = best
        others = " + ".join(x for x in keys if x != key)
        rounds[at] = replace(rnd, winner=c, group=(c, key) + tuple(x for x in rnd.group if x not in (c, key)),
                             tie=None, basis=f"{rnd.basis}; re-selected after the search: with {others} in, {c} in "
                                         f"place of {key} gains {100 * g:.1f} % on the selection windows (its "
                                         f"{100 * q:.0f} % bootstrap quantile {100 * lo:.1f} %, threshold "
                                         f"{100 * rnd.threshold:.1f} %)")
        model, keys, changed = res, keys[:k] + [c] + keys[k + 1:], True
    return model, keys, changed
