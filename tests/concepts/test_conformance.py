"""check_concept over every registered concept, plus exact frame balance on spliced sets."""

import numpy as np
import pytest

from voe.concepts import CONCEPTS, SUITES, get_concept
from voe.concepts.check import check_concept
from voe.sim.scene import SimConfig
from voe.testing import PixelSumModel


@pytest.mark.parametrize("concept_id", CONCEPTS.ids())
def test_check_concept(concept_id):
    check_concept(get_concept(concept_id), n_sets=6, seed=3)


def test_core_suite_is_fully_registered():
    for name in SUITES["core"]:
        assert name in CONCEPTS, f"core concept {name} is not registered"


@pytest.mark.parametrize("concept_id", [c for c in CONCEPTS.ids() if get_concept(c).kind == "quadruplet"])
def test_frame_only_scorer_ties_exactly_on_spliced_sets(concept_id):
    from voe.io.batch import Batch
    from voe.sim.scene import FEATURE_NAMES

    c = get_concept(concept_id)
    model = PixelSumModel()
    for i in range(4):
        m = c.make_set(i, 11, SimConfig())
        surprise = {}
        for clip in m.clips:
            r = clip.rec
            b = Batch(r.frames[None], r.states[None], r.present[None], FEATURE_NAMES, 0.05)
            surprise[clip.variant] = model.frame_nll(b).sum()
        assert surprise["A"] + surprise["B"] == pytest.approx(surprise["AB"] + surprise["BA"], rel=0, abs=1e-6)
        assert not np.isclose(surprise["A"], surprise["B"]) or c.name != "permanence"
