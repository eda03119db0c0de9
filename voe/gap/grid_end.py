"""A one-parameter fit left where its coarse grid stopped: not a fit as it stands
(``beyond_grid``), and what the check reports instead (``past_grid``).

Why a module of its own: the check step (``voe.gap.check``) asks these two questions of the
model it is about to report, and they share one notion, the grid a one-parameter fit screened
(``voe.gap.fit.scalar_grid``, ``FitResult.grid_end``), which nothing else in the check uses.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.gap.effects.base import FitContext
from voe.gap.fit import FitResult, scalar_grid
from voe.gap.folds import FoldedFitter, as_sum
from voe.gap.uncertainty import established


def beyond_grid(fitter: FoldedFitter, model: FitResult) -> str | None:
    """Why ``model``, one part with one parameter left at the outermost point of the coarse grid
    its fit screened (``FitResult.grid_end``), is not reported: in some fold the fitting cost, on
    the windows that fit chose (``Fitter.focused`` for a sparse part), is lower at the next point
    of the grid around that value (``Effect.grid``, inside the bounds) than at the value itself;
    None if it is not, in every fold.

    Why: such a value is not a fit but the place the search stopped. The refine step goes on
    from it, and its result is kept only if it does not lose on the selection windows
    (``voe.gap.search.accept``); when it loses, the grid's end is named, a value neither the
    fitting windows (they want more) nor the selection windows (they wanted less) chose. A
    missing library effect is fitted where its strength lies; physics outside the library
    fitted by it is not. Development case 6685146 (a floor patch) named ``mass[box]`` 3.3,
    the last of ``Mass.RATIOS``: on the 6 collision windows its fit chose the cost falls on to
    7 (48912 at 3.3, 46671 at 4, 45178 at 7), while the selection gain peaks at 2.5 (18.9 %)
    and is 8.6 % at 7, short of the round's 17.5 %. A true mass (6685007, 2.15) is fitted
    inside the grid (2.14; cost 10734 at 2, 12929 at 3.3). Not asked of a value at a bound
    (nothing lies beyond), nor of a Brent result (a minimum between two grid points). Since
    session 43 a fit whose minimum sits at its grid's end walks on outward (``voe.gap.fit._walk``;
    6685146's scan now fits about 7 in the search itself), so only a walk that ran out of steps
    inside the bounds leaves such a value.
    """
    part = model.effect.parts[-1]
    for f, v in zip(fitter.folds, model.fold_params, strict=True):
        lo, hi = model.effect.bounds(f.ctx)
        scale = model.effect.scale(f.ctx)
        grid = scalar_grid(model.effect, v, lo, hi, scale)
        on = f.focused(model.effect, v, lo, hi, scale)
        here = on.cost(model.effect, v)
        for g in (grid[grid < v[0]][-1:], grid[grid > v[0]][:1]):  # the neighbours below and above
            beyond = on.cost(model.effect, g) if g.size else np.inf
            if beyond < here:
                return (f"{part.name} = {float(v[0]):.3g} is the end of the grid its fit searched, and the fitting "
                        f"cost is lower at {float(g[0]):.3g} ({beyond:.4g} against {here:.4g}): "
                        f"the value is where the search stopped, not a fit")
    return None


def past_grid(fitter: FoldedFitter, model: FitResult, bar: Callable[[FitResult], str | None],
              bounded: Callable[[FitResult], tuple[np.ndarray, np.ndarray]],
              ctx: FitContext) -> tuple[FitResult, np.ndarray, np.ndarray] | str:
    """``model`` (one parameter left where its grid stopped, the fitting cost falling on beyond:
    ``beyond_grid``) refitted from there, as (model, lower, upper) when the refit is a fit the
    check reports: the fitting windows' minimum is inside the refit's grid (no ``beyond_grid``
    again), it passes ``bar`` (``short_of_nominal`` on the selection windows, as any reported
    model does), its interval (``bounded``: ``model_intervals``) establishes it and, cross-fitted,
    holds every fold's value; else why not, as a clause for ``beyond_grid``'s reason.

    Why: the search's refine step (``voe.gap.search.accept``) already fits on from the grid's end,
    but keeps the refit only if it does not lose to the grid's end on the selection windows, so a
    hair's loss there left a true effect at a value nobody chose and ``beyond_grid`` dropped it.
    Untouched case 2307044 (session 27's cross-fitted run, development since it was traced): a
    true ``joint_friction`` 0.0200 (expressed in 20 of 50 selection windows) stopped at 0.0192 in
    one fold, whose fitting cost was lower at 0.0211 (2092 against 2123); the gain at 0.0192 was
    57.8 % (5 % quantile 53.2 %, threshold 5 %) and the effect was dropped, verdict ``consistent``.
    What ``beyond_grid`` guards against still fails here: a stand-in for physics outside the
    library runs on past the refit's grid, or, where the fitting windows want it, gains too little
    on the selection windows (development case 6685146, ``mass[box]`` for a floor patch: its
    fitting cost falls on to 7, where the selection gain is 8.6 % against the round's 17.5 %).

    The folds must agree because the refit is where a stand-in gets through: cross-fitted, each
    fold fits the value on its own half of the episodes; the model's value is their median (with two
    folds, their mean), and its interval is fitted on all the episodes. A real effect's halves lie on
    either side of that value, each off it by about the standard error of a fit on all the episodes,
    so outside its 95 % interval together about 5 % of the time; a stand-in fits each half's own mix
    of the missing physics. Development case 2307140 (a floor patch of other
    friction; traced in session 31): ``friction`` stopped at its grid's end in both folds (1.67,
    1.45), refitted 1.98 and 0.73, interval [0.99, 1.50]: without this it was named. The true
    effects above: 2307044 0.0204 and 0.0193 in [0.0171, 0.0237]; 2307046 (``mass[box]``, true
    2.96) 7.19 and 2.29 in [1.92, 13.5]. The three-way split has one fold (the model's own value),
    and nothing is asked.
    """
    ref = as_sum(fitter.refine(model))
    if ref.grid_end and beyond_grid(fitter, ref) is not None:
        return f"; refitted from there it stops at the end of its grid again ({_values(ref)})"
    there = f"; refitted where the fitting windows want it ({_values(ref)}), "
    why = bar(ref)
    if why is not None:
        return there + why
    lo, hi = bounded(ref)
    if not all(established(ref.effect, lo, hi, ctx)):
        return there + "its 95 % interval contains the nominal value"
    if len(ref.fold_params) > 1 and any(not lo[0] <= v[0] <= hi[0] for v in ref.fold_params):  # halves' fits
        return there + f"the folds disagree: its 95 % interval [{lo[0]:.3g}, {hi[0]:.3g}] does not hold every fold's value"
    return ref, lo, hi


def _values(res: FitResult) -> str:
    """Each fold's value of a one-parameter model, for a reason's text."""
    return ", ".join(f"{float(v[0]):.3g}" for v in res.fold_params)
