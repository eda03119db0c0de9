"""The bench's expression diagnostic: how many selection windows a concealed truth moves."""

from types import SimpleNamespace

import numpy as np

from voe.gap.bench import Case, expression
from voe.gap.bench_score import expression_lines
from voe.gap.shooting import Shooter, make_windows

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
