"""The final model must not leave the typical test window departing more than the nominal model
does (``voe.gap.check.worse_on_test``)."""

from __future__ import annotations

import numpy as np

import voe.gap.check as check
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.verify import Verification

RR = EffectSum((EFFECTS.get("rolling_resistance")(),))


def _checked(median_before: float, median_after: float) -> check.Checked:
    ver = Verification(0.088, 0.070, 0.0, 0.0, 0.0, 0.0, median_before, median_after, 1.0, 0.67, False)
    model = FitResult(RR, np.array([0.048]), 0, 0, np.ones(3))
    return check.Checked(model, ("rolling_resistance",), np.array([0.02]), np.array([0.05]), (), ver, "test",
                         np.zeros(1))


def test_a_model_that_leaves_the_median_test_window_departing_more_is_not_reported(monkeypatch):
    nominal = Verification(0.088, 0.088, 0.0, 0.0, 0.0, 0.0, 18.6, 18.6, 1.0, 1.0, False)
    monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (nominal, "test"))
    # development case 6685149 (a gust named ``rolling_resistance``): median window z 18.6 -> 24.4, threshold 5.0
    out = check.worse_on_test(_checked(18.6, 24.4), None, None, 5.0)
    assert out.model is None and out.keys == () and out.verification is nominal
    assert "does not carry over" in out.dropped[0]["reason"]
    c = _checked(18.6, 9.5)  # better than nominal: kept
    assert check.worse_on_test(c, None, None, 5.0) is c
    c = _checked(1.2, 1.4)  # worse, but the typical window does not depart: kept
    assert check.worse_on_test(c, None, None, 5.0) is c
