"""The bench's expression diagnostic: how many selection windows a concealed truth moves, and how
many of the location's windows a floor patch moves."""

from types import SimpleNamespace

import numpy as np

from voe.gap.bench import Case, expression, make_case
from voe.gap.bench_score import expression_lines, outside_expression_lines
from voe.gap.finder import ALL_EFFECTS
from voe.gap.shooting import Shooter, make_windows
from voe.gap.stages import GapConfig, prepare

from .conftest import flight_episodes


def test_expression_counts_the_windows_a_truth_moves_beyond_the_noise():
    scene, eps = flight_episodes(n=2, duration=1.0, seed=5)
    sh = Shooter(scene, eps, 1e-3)
    wins = make_windows(eps, [0, 1], 0.5)  # 4 windows of 0.5 s of free flight at 4-8 m/s
    finder = SimpleNamespace(problem_=SimpleNamespace(shooter=sh), search_=SimpleNamespace(fitter=SimpleNamespace(test=wins)))

    def case(c: float) -> Case:
        return Case(scene, "linear_drag", np.array([c]), None, eps, {"linear_drag": (np.array([c]), None)})

    assert expression(case(0.5), finder, 1e-3) == (4, 4)  # drag 0.5 /s: centimetres within 0.5 s
    assert expression(case(1e-5), finder, 1e-3) == (0, 4)  # about 1e-5 m: far below 3 mm
    assert sh.n_rollouts == 0  # the diagnostic is not counted as the finder's work
    none = Case(scene, "none", np.zeros(0), None, eps, {})
    assert expression(none, finder, 1e-3) is None


def test_expression_lines_split_identification():
    rows = [{"truth": "mass", "found": "mass", "expressed": (4, 9)},
            {"truth": "mass", "found": "none", "expressed": (1, 9)},
            {"truth": "friction", "found": "none", "expressed": (2, 7)},
            {"truth": "friction", "found": "friction", "expressed": (3, 7)},
            {"truth": "none", "found": "none", "expressed": None}]
    (line,) = expression_lines(rows)
    assert "in 3 or more windows 2/2 = 100 %; in fewer 0/2 = 0 %" in line
    assert expression_lines([rows[-1]]) == []


def test_a_floor_patch_is_expressed_on_the_location_windows():
    """Development case 3511146, a floor patch left ``consistent`` by its untouched run: the patch
    moves 3 of its 21 location windows by more than 3 mm (up to 71 mm). The same recordings
    judged against their own nominal scene move none: the count is the patch's, not the noise's."""
    case = make_case(np.random.default_rng(3511146), "floor_patch")
    assert case.sim_scene is not None and case.sim_scene != case.scene
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, GapConfig())
    wins = make_windows(p.episodes, list(range(len(p.episodes))), GapConfig().locate_window, bad_start=p.bad)
    finder = SimpleNamespace(problem_=p, search_=SimpleNamespace(fitter=SimpleNamespace(test=wins[:2])),
                             location_=SimpleNamespace(windows=wins))
    assert expression(case, finder, 1e-3) == (3, len(wins)) and len(wins) == 21
    same = Case(case.scene, "floor_patch", case.params, None, case.episodes, case.true, sim_scene=case.scene)
    assert expression(same, finder, 1e-3) == (0, 21)
    assert make_case(np.random.default_rng(3511145), "gust").sim_scene is None  # a gust: same scene, not simulated


def test_outside_expression_lines_split_the_out_of_library_verdicts():
    rows = [{"truth": "floor_patch", "names": [], "verdict": "consistent", "located": 0, "expressed": (2, 23)},
            {"truth": "floor_patch", "names": [], "verdict": "unexplained", "located": 4, "expressed": (4, 17)},
            {"truth": "floor_patch", "names": ["friction_region"], "verdict": "mismatch", "located": 3,
             "expressed": (9, 20)},
            {"truth": "floor_patch", "names": [], "verdict": "consistent", "located": 4, "expressed": (3, 21)},
            {"truth": "gust", "names": [], "verdict": "unexplained", "located": 12, "expressed": None}]
    (line,) = outside_expression_lines(rows)
    assert "floor patch moves a location window's" in line and "in 3 or more windows 2/3 = 67 %; in fewer 0/1 = 0 %" in line
    assert outside_expression_lines([rows[-1]]) == []
