"""Earning a place: the model without a part is refitted also from the parts' own round values."""

from types import SimpleNamespace

import numpy as np

from voe.gap.check import _refit_without
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.search import Round


class _Fitter:
    """Refits nothing: the training cost is the distance of the start from ``best`` (two folds)."""

    def __init__(self, best: np.ndarray) -> None:
        self.best, self.starts = best, []
        self.config = SimpleNamespace(refine_nfev=20)

    def refit(self, effect, fold_starts, max_nfev=None):
        self.starts.append(fold_starts)
        cost = float(sum(np.sum((s - self.best) ** 2) for s in fold_starts))
        return FitResult(effect, fold_starts[0], cost, 0.0, np.ones(3), tuple(fold_starts))


def test_without_a_part_the_rest_restarts_from_its_own_round_and_the_cheaper_fit_wins():
    ca, fr = EFFECTS.get("constant_acceleration")(), EFFECTS.get("friction_region")()
    both = EffectSum((ca, fr))
    own = np.array([-0.17, 0.78])  # round one's acceleration, before friction_region was fitted next to it
    bent = np.array([-0.15, 0.72, -0.13, -3.0, -0.5])  # the two-part model: the acceleration bent by the second part
    model = FitResult(both, bent, 1.0, 0.0, np.ones(3), (bent, bent))
    round1 = Round(1.0, {"constant_acceleration": FitResult(ca, own, 1.0, 0.0, np.ones(3), (own, own))},
                   {}, {}, 0.05, "constant_acceleration")
    rounds = {"constant_acceleration": round1}
    keys = ["constant_acceleration", "friction_region"]

    fitter = _Fitter(own)  # the acceleration's own values fit best
    red = _refit_without(SimpleNamespace(fitter=fitter), model, keys, 1, rounds)
    assert len(fitter.starts) == 2
    np.testing.assert_allclose(fitter.starts[1][0], own)
    np.testing.assert_allclose(red.params, own)

    fitter = _Fitter(bent[:2])  # the bent values fit best: they are kept
    red = _refit_without(SimpleNamespace(fitter=fitter), model, keys, 1, rounds)
    np.testing.assert_allclose(red.params, bent[:2])

    fitter = _Fitter(own)  # no round of its own for what is left (a group member took over): one refit
    _refit_without(SimpleNamespace(fitter=fitter), model, keys, 1, {})
    assert len(fitter.starts) == 1
