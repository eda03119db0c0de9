"""A parameter draw that a design cannot be built from is redrawn, deterministically."""

from __future__ import annotations

import numpy as np
import pytest

from tests.concepts.helpers import balanced
from voe.concepts import get_concept
from voe.errors import ConceptError
from voe.sim.scene import SimConfig


def test_unbuildable_draw_is_redrawn_and_recorded():
    # Unchangeableness-v3 set 11 of seed 8111 first draws a morph with no frame behind the screen
    # (it failed a whole probe set before redraws existed)
    c = get_concept("Unchangeableness-v3")
    m1, m2 = (c.make_set(11, 8111, SimConfig(size=64)) for _ in range(2))
    assert m1.params["redraws"] >= 1
    assert m1.params == m2.params
    for x, y in zip(m1.clips, m2.clips, strict=True):
        assert np.array_equal(x.rec.frames, y.rec.frames)
    assert balanced(*(cl.rec for cl in m1.clips))


def test_first_draw_sets_record_no_redraws():
    m = get_concept("Unchangeableness-v3").make_set(0, 0, SimConfig(size=64))
    assert "redraws" not in m.params


def test_never_buildable_gives_one_line(monkeypatch):
    c = get_concept("Permanence-v2")

    def broken(*_a, **_k):
        raise ValueError("no candidate frame for test in [0, 0)")

    monkeypatch.setattr(type(c), "_possible_pair", broken)
    with pytest.raises(ConceptError, match=r"no buildable draw in 50 tries; last: no candidate frame"):
        c.make_set(3, 0, SimConfig(size=64))
