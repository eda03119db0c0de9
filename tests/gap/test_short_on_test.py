"""The second look's name must lower the test-split RMSE by a practical margin
(``voe.gap.check.short_on_test``)."""

from __future__ import annotations

import numpy as np

import voe.gap.check as check
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.fit import FitResult
from voe.gap.stages import GapConfig
from voe.gap.verify import Verification

RR = EffectSum((EFFECTS.get("rolling_resistance")(),))


def _checked(before: float, after: float) -> check.Checked:
    ver = Verification(before, after, 0.0, 0.0, 0.0, 0.0, 2.0, 2.0, 0.1, 0.1, True)
    model = FitResult(RR, np.array([0.0032]), 0, 0, np.ones(3))
    return check.Checked(model, ("rolling_resistance",), np.array([0.002]), np.array([0.005]), (), ver, "test",
                         np.zeros(1))


def test_a_second_look_name_that_barely_lowers_the_test_rmse_is_not_reported(monkeypatch):
    nominal = Verification(0.00232, 0.00232, 0.0, 0.0, 0.0, 0.0, 2.0, 2.0, 0.1, 0.1, True)
    monkeypatch.setattr(check, "verify_on_test", lambda p, model, config, z: (nominal, "test"))
    # development case 6774226 (clean, coloured noise): the second look named rolling_resistance 0.0032,
    # test RMSE 2.32 -> 2.27 mm
    out = check.short_on_test(_checked(0.00232, 0.002274), None, GapConfig(), 5.0)
    assert out.model is None and out.keys == () and out.verification is nominal
    assert out.dropped[0]["effect"] == "rolling_resistance" and "2.0 %" in out.dropped[0]["reason"]
    c = _checked(0.0105, 0.00882)  # 6774016's right rolling_resistance, 16.0 %: kept
    assert check.short_on_test(c, None, GapConfig(), 5.0) is c
    c = _checked(0.00232, 0.002274)  # the bar is a setting: 0 keeps every name
    assert check.short_on_test(c, None, GapConfig(second_look_test_gain=0.0), 5.0) is c
    c = _checked(0.00232, 0.00232).__class__(None, (), np.zeros(0), np.zeros(0), (), nominal, "test", np.zeros(0))
    assert check.short_on_test(c, None, GapConfig(), 5.0) is c  # nothing named: nothing to drop
