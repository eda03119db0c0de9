"""check_concept over every registered concept, plus exact frame balance on spliced sets."""

import numpy as np
import pytest

from voe.concepts import CONCEPTS, SUITES, get_concept
from voe.concepts.check import check_concept
from voe.sim.scene import SimConfig
from voe.testing import PixelSumModel


@pytest.mark.parametrize("concept_id", CONCEPTS.ids())
def test_check_concept(concept_id):
    check_concept(get_concept(concept_id), n_sets=6, seed=(3, 4, 5))  # balance claims on every set
    # coarse frames: an object within a pixel of a screen's edge shows, so screens need the room
    check_concept(get_concept(concept_id), n_sets=6, seed=6, cfg=SimConfig(size=32))


def test_core_suite_is_fully_registered():
    for name in SUITES["core"]:
        assert name in CONCEPTS, f"core concept {name} is not registered"


def _carrying(level: str) -> list[str]:
    """Concepts that claim ``level`` on every condition that carries the verdict."""
    out = []
    for cid in CONCEPTS.ids():
        c = get_concept(cid)
        claims = [c.balance.get(cond, "") for cond in c.conditions if cond != "perceptual"]
        if claims and all(level in cl.split("+") for cl in claims):
            out.append(cid)
    return out


def test_every_core_concept_balances_frames_and_motion_where_it_carries_a_verdict():
    assert set(_carrying("F")) == set(_carrying("M")) == set(CONCEPTS.ids())


@pytest.mark.parametrize("concept_id", _carrying("M"))
def test_knowledge_free_scorers_tie_exactly_where_the_verdict_is_carried(concept_id):
    """Per-frame pixel sums, motion energy and mean object height: the same totals on both sides."""
    from voe.io.batch import Batch
    from voe.sim.scene import FEATURE_NAMES

    c = get_concept(concept_id)
    model = PixelSumModel()
    n = 0
    for i in range(6):
        m = c.make_set(i, 11, SimConfig())
        if not m.carries_verdict:
            continue
        n += 1
        tot = {"possible": np.zeros(3), "impossible": np.zeros(3)}
        for clip in m.clips:
            r = clip.rec
            b = Batch(r.frames[None], r.states[None], r.present[None], FEATURE_NAMES, 0.05)
            motion = np.abs(np.diff(r.frames.astype(np.int64), axis=0)).sum()
            height = np.nansum(r.states[..., FEATURE_NAMES.index("y")])
            tot[clip.role] += (model.frame_nll(b).sum(), motion, height)
        np.testing.assert_allclose(tot["possible"], tot["impossible"], rtol=0, atol=1e-3)
    assert n >= 3
