"""Frame-only scorers tie exactly on every spliced quadruplet (an empirical proof of balance)."""

import pytest

from voe.concepts import CONCEPTS, get_concept
from voe.controls.frame_only import PixelDensity, RandomFeatureScorer
from voe.scoring.runs import load_run
from voe.scoring.score import score_probe_set
from voe.scoring.table import set_table

SPLICED = [c for c in CONCEPTS.ids() if get_concept(c).kind == "quadruplet"]


@pytest.mark.parametrize("model", [PixelDensity(), RandomFeatureScorer(seed=0), RandomFeatureScorer(seed=7)],
                         ids=lambda m: m.name)
def test_frame_only_scorers_are_exactly_at_chance_on_spliced_concepts(model, tiny_probes, tmp_path):
    score_probe_set(model, tiny_probes, tmp_path / "run")
    sets = set_table(load_run(tmp_path / "run"))
    spliced = sets[sets["concept"].isin(SPLICED)]
    assert set(spliced["concept"]) == set(SPLICED)
    assert (spliced["accuracy"] == 0.5).all(), spliced[["set_id", "s_imp", "s_pos"]]


def test_pixel_density_is_a_normalised_per_frame_likelihood():
    import numpy as np

    from voe.io.batch import Batch

    frames = np.zeros((1, 2, 2, 2), dtype=np.uint8)
    frames[0, 1, 0, 0] = 255
    d = PixelDensity(probs=np.full((2, 2), 0.25))
    b = Batch(frames, np.zeros((1, 2, 1, 11), np.float32), np.ones((1, 2, 1), bool), tuple("abcdefghijk"), 0.05)
    nll = d.frame_nll(b)
    # frame 0: all four pixels off: -4 log 0.75; frame 1: one on: -log .25 - 3 log .75
    assert nll[0, 0] == pytest.approx(-4 * np.log(0.75))
    assert nll[0, 1] == pytest.approx(-np.log(0.25) - 3 * np.log(0.75))
