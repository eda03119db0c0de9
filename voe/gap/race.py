"""The race between a round's candidates, run on refined fits.

Why: every candidate of a round gets the same short first fit, and only the round's winner was
then refined (``voe.gap.search.accept``: a longer fit from its own parameters). A true law whose
first fit stopped in a worse valley than a rival's lost the race on that fit and was never
refined. Development seed 6219, round 1, fold-level (``docs/bench-runs/dev-s44``):

- 6219041 (a true ``constant_acceleration``): ``spring_anchor`` 0.872, ``constant_acceleration``
  0.847 (Powell stopped at (0.546, 0.427) for a truth of (0.603, 0.334)); refined, 0.871 and
  0.887. ``spring_anchor`` was named, with its anchor at the bound of its range.
- 6219010 (a true ``restitution`` 0.222): ``restitution_region`` 0.967, ``restitution`` 0.905
  (the grid stepped over the true valley and Brent settled at 0.097); refined, 0.967 and 0.970
  (0.222). ``restitution_region`` was named.

So the contenders (the candidates whose first-fit gain beats the round's threshold, at most
``RACE`` of them, best first) are refined before the group is formed, and the race is run on
their refined gains. Only the naming changes: which candidates can pass is decided on the first
fits, as before (gain above the threshold, which the null calibrates on first fits, and the
bootstrap lower bound of the first fit, kept as it was: on development floor patch 6219146 a
refined ``friction_region``'s bound turned positive where its first fit's was not, which would
have let the refine decide how it is accepted). The same holds for the tests a provisional
winner (``voe.gap.greedy.Trial``) faces: the next round's confirmation, ``mostly_better`` and the
pair step after an undone trial see the rounds' first fits, since each decides what can pass
(and the thresholds they compare with, the null's pair step among them, come from first fits);
the rounds record the refined contenders (their gains decided the race, and the report shows
them). A refined fit is kept only if it does not lose
(the refine step's rule), so a contender's gain can only rise. The winner is not refined again.

The refine can only add members to the round's group, never remove one (``race_group``). Why: a
longer fit helps a more flexible rival more. Development case 6219106 (a true
``constant_acceleration``): first fits ``spring_anchor`` 0.889 and ``constant_acceleration``
0.880, one group; refined, 0.907 and 0.881, and the constant force fell out of the group (its
error 28 % above the spring's). The spring was then dropped by the check, and with no other
member to try, the true law went unnamed. Indistinguishable on first fits stays
indistinguishable; which member wins is then decided on the refined fits (``tie_break``).
"""

from __future__ import annotations

import numpy as np

from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter
from voe.gap.search import accept_all, choose, window_gain

RACE = 3  # contenders refined before a race: the cost is RACE - 1 refine steps per round with a race


def contenders(gains: dict[str, float], threshold: float | None, k: int = RACE) -> list[str]:
    """The (at most ``k``) candidates whose gain beats ``threshold``, best first; [] unless two do.

    Why two: with one candidate above the threshold there is no race, and the winner's refine
    step comes anyway. Ties keep pool order (``sorted`` is stable), as ``choose`` does.
    """
    if threshold is None:
        return []
    above = sorted((key for key, g in gains.items() if g > threshold), key=lambda key: -gains[key])
    return above[:k] if len(above) >= 2 else []


def refined_race(fitter: FoldedFitter, results: dict[str, FitResult], gains: dict[str, float],
                 threshold: float | None, before_sse: np.ndarray,
                 n_jobs: int = 1) -> tuple[dict[str, FitResult], dict[str, float], set[str]]:
    """The round's (results, gains) with the contenders refined, and the contenders' keys.

    Args:
        results, gains: the round's first fits and their gains against ``before_sse`` (W,).
        threshold: the round's threshold (None: the null's round was skipped, nothing can pass).

    Returns:
        New dicts (the inputs are not changed; keys in the same order) and the contenders' keys,
        whose results are final: ``accept`` would only refine them again.
    """
    keys = contenders(gains, threshold)
    if not keys:
        return results, gains, set()
    refined = accept_all([(fitter, results[k], gains[k], before_sse) for k in keys], n_jobs)
    results, gains = dict(results), dict(gains)
    for key, res in zip(keys, refined, strict=True):
        if res is not results[key]:  # else the refine lost: the first fit stands, and its gain
            results[key], gains[key] = res, window_gain(before_sse, res.window_sse)
    return results, gains, set(keys)


def race_group(first: dict[str, float], gains: dict[str, float], lower: dict[str, float],
               threshold: float | None) -> list[str]:
    """``choose`` on the refined ``gains``, joined by the members of the first fits' group
    (``first``: the round's gains before ``refined_race``), best refined gain first.

    Why: see the module docstring (6219106). Without a race ``first`` is ``gains`` and this is
    ``choose``.
    """
    if threshold is None:
        return []
    keys = set(choose(gains, lower, threshold)) | set(choose(first, lower, threshold))
    return sorted((k for k in gains if k in keys), key=lambda k: -gains[k])  # stable: ties in pool order
