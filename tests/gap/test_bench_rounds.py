"""A bench case's stored record keeps each greedy round's path (winner, group, threshold, basis), so
the cases that reach one path of the search can be found in a store without running them again."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np

import voe.gap.bench as bench
from voe.gap.search import Round

REFUSED = "friction won, but with rolling_resistance it does not beat the model before the trial: both undone"


def _round(winner, threshold, basis, group=()):
    return Round(before=0.01, results={}, gains={"friction": 0.158, "mass": np.float64(0.006)}, lower={},
                 threshold=threshold, winner=winner, group=tuple(group), basis=basis)


def test_round_record_is_small_and_json():
    rows = [bench.round_record(_round("mass[box]", np.float64(0.15023), "named by the located context",
                                      ("mass[box]", "mass[ball]"))),
            bench.round_record(_round(None, None, REFUSED)),
            bench.round_record(_round(None, float("nan"), ""))]
    assert rows == [["mass[box]", ["mass[box]", "mass[ball]"], 0.1502, "named by the located context"],
                    [None, [], None, REFUSED], [None, [], None, ""]]
    assert json.loads(json.dumps(rows)) == rows  # stored as JSON lines, numpy scalars converted


class _Finder:
    """What ``run_case`` reads of a fitted finder: nothing named, two rounds."""

    def __init__(self, **kw):
        self.effects_, self.verdict_, self.groups_, self.located_ = [], "consistent", [], []
        self.checked_ = SimpleNamespace(dropped=[])
        self.fit_ = {"before": 0.01, "after": 0.01}
        self.rounds_ = (_round(None, 0.05, "rolling_resistance was tried provisionally and not confirmed"),
                        _round(None, 0.05, REFUSED))

    def fit(self, scene, episodes):
        return self


def test_a_case_record_holds_its_rounds(monkeypatch):
    monkeypatch.setattr(bench, "GapFinder", _Finder)
    rec = bench.run_case((7001, "none", 1e-3, 3, 2, 1.0, "white"))
    assert [r[3] for r in rec["rounds"]] == ["rolling_resistance was tried provisionally and not confirmed", REFUSED]
    assert rec["verdict"] == "consistent" and json.loads(json.dumps(rec["rounds"])) == rec["rounds"]
