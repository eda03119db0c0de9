"""gap.md: written with and without figures (and the progress has a total), and a tied group called indistinguishable only when
no selection window told its members apart."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from voe.gap.jitter import Jitter
from voe.gap.report import markdown
from voe.gap.run import diagnose
from voe.gap.search import TieBreak


def _finder(groups, ties, jitter=None):
    """The attributes ``markdown`` reads, for one accepted effect and its round's group."""
    fit = {"before": 1e-3, "after": 5e-4, "position_before": 1e-3, "position_after": 5e-4, "median_z_before": 3.0,
           "median_z_after": 1.0, "on": "test episodes [5]", "threshold_gain": 0.1}
    effect = {"name": groups[0][0], "params": {"b": 1.5e-4}, "interval95": {"b": [1.4e-4, 1.6e-4]},
              "units": {"b": "N m s"}, "acts": "always", "bodies": ["arm"]}
    return SimpleNamespace(fit_=fit, verdict_="mismatch", explanation_="text",
                           problem_=SimpleNamespace(split=SimpleNamespace(note="three-way split"), jitter=jitter),
                           effects_=[effect], groups_=groups, _kept_rounds=lambda: [SimpleNamespace(tie=t) for t in ties],
                           checked_=SimpleNamespace(dropped=()), located_=[])


def test_a_group_decided_on_windows_is_not_called_indistinguishable():
    md = markdown(_finder([["angular_damping", "linear_drag"]], [TieBreak(18)]), [])
    assert "Indistinguishable" not in md
    assert "angular_damping chosen on the 18 selection windows" in md and "linear_drag fit those windows within 10 %" in md
    md = markdown(_finder([["angular_damping", "linear_drag"]], [TieBreak(3, ("linear_drag",))]), [])
    assert "Indistinguishable" not in md and "too few windows to rule out linear_drag" in md
    md = markdown(_finder([["angular_damping", "linear_drag"]], [None]), [])
    assert "Indistinguishable on these data" in md and "angular_damping, linear_drag" in md
    md = markdown(_finder([["angular_damping"]], [None]), [])
    assert "Indistinguishable" not in md and "chosen on" not in md


def test_gap_md_says_when_the_clean_data_reproduce_timing_jitter():
    assert "jitter" not in markdown(_finder([["angular_damping"]], [None]), [])
    md = markdown(_finder([["angular_damping"]], [None], Jitter(1.96e-3, np.full((1, 3), 1e-3))), [])
    assert "off their time stamps by about 2 ms (timing jitter" in md


def test_no_figures_still_writes_gap_md_and_the_progress_has_a_total(flight_files, tmp_path):
    scene, rec = flight_files
    out = tmp_path / "out"
    steps, totals = [], []
    diagnose(scene, rec, out, ["linear_drag"], figures=False, progress=steps.append, total=totals.append)
    assert totals == [5] and len(steps) <= 5  # locate, the candidate on the data and the null, check, drift
    md = (out / "gap.md").read_text()
    assert md.startswith("# Sim-to-real gap:") and "## Effects" in md
    assert "![" not in md and "## Figures" not in md
    assert sorted(p.name for p in out.iterdir()) == ["gap.json", "gap.md"]
