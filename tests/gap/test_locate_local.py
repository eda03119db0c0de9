"""The second bar of the location (``voe.gap.stages.locate_parts``): when nothing passes the clean
replicate's bar but the data depart as a whole, windows above every one of their own window-local
clean replicates are located. Both ways, on bench cases of development seed 7241 (the locate stage
alone, the finder's own draws): a gust its untouched run left ``consistent`` is now located and
``unexplained``; a clean case with windows above their own replicates, whose departure p is not
below ALPHA, stays unlocated and ``consistent``."""

from __future__ import annotations

import numpy as np

from voe.gap.bench import make_case, plan
from voe.gap.departure import ALPHA
from voe.gap.finder import ALL_EFFECTS, unnamed_verdict
from voe.gap.stages import GapConfig, locate_step, prepare
from voe.gap.verify import explain


def _locate(seed: int):
    rows = plan(130, 7241, 180, compound=8, outside=12, clean_kinds=("coloured", "white"))
    s, truth, noise_kind, _ = rows[seed - 7241000]
    assert s == seed
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=noise_kind)
    config = GapConfig()
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
    return truth, locate_step(p, config, np.random.default_rng(seed))


def test_a_gust_under_the_one_bar_is_located_against_its_windows_own_replicates():
    truth, loc = _locate(7241143)
    assert truth == "gust"
    assert loc.departure_p < ALPHA  # 0.0004: the data depart as a whole
    assert loc.located and all(x["bar"] == "local" for x in loc.located)  # none passed z_threshold
    assert all(x["z"] > x["bar_z"] >= GapConfig().z_min for x in loc.located)
    assert unnamed_verdict(loc.located, loc.departure_p) == "unexplained"


def test_a_clean_case_with_windows_above_their_replicates_but_no_departure_is_not_located():
    truth, loc = _locate(7241219)
    assert truth == "none"
    assert ALPHA <= loc.departure_p < 0.05  # 0.014: three windows above their own replicates, not enough
    assert loc.located == []
    assert unnamed_verdict(loc.located, loc.departure_p) == "consistent"


def test_the_explanation_says_which_bar_located_a_stretch():
    from voe.gap.verify import Verification
    nan = float("nan")
    ver = Verification(nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, False)
    x = {"episode": 3, "body": "ball", "t_start": 1.0, "t_end": 2.0, "variables": ["x"], "context": "rolling",
         "z": 14.2, "region": [0.1, 0.4, 0.0, 0.1], "bar": "local", "bar_z": 9.3}
    text = explain("unexplained", [], [], [x], ver, 0.08, np.full((1, 3), 1e-3), "test", 21.2, departure_p=4e-4)
    assert "each of these windows is above every window-local clean replicate" in text
    assert "bar 9.3" in text and "21.2" in text and "z = 5;" in text
    clean = {**x, "z": 30.0, "bar": "clean", "bar_z": 21.2}
    text = explain("unexplained", [], [], [clean], ver, 0.08, np.full((1, 3), 1e-3), "test", 21.2, departure_p=4e-4)
    assert "1 located stretch(es) (z above 21.2)" in text and "window-local" not in text


def test_gap_md_names_the_local_bar_as_the_explanation_does():
    from voe.gap.report import _bar
    assert _bar({"bar": "local", "bar_z": 9.3}, 5.0) == "9.3: each window above its own clean replicates and z = 5"
    assert _bar({"bar": "clean", "bar_z": 21.2}, 5.0) == "21.2: the clean replicate's 95th-percentile window z"
