"""The lesion registry: every lesion declares every concept, and breaks what it declares."""

from pathlib import Path

import pytest

from voe.concepts import CONCEPTS
from voe.concepts.generate import generate_probe_set
from voe.controls.builtin import lesion_controls
from voe.controls.lesion_registry import LESIONS, Lesion, get_lesion, undeclared
from voe.controls.lesions import LesionedOracle
from voe.controls.spec import EXPECTATIONS
from voe.errors import UnknownNameError
from voe.io.probeset import load_probe_set
from voe.models.oracle import PhysicsOracle
from voe.scoring.runs import load_run
from voe.scoring.score import score_probe_set
from voe.scoring.table import set_table
from voe.sim.scene import SimConfig
from voe.world.generate import generate_world

#: Declarations that claim the lesion breaks a concept (``not-learned``: never learned, maybe below chance).
BREAKS = ("fail", "chance", "not-learned")
CONCEPT_NAMES = sorted({c.split("-v")[0].lower() for c in CONCEPTS.ids()})


@pytest.mark.parametrize("lesion", list(LESIONS))
def test_every_lesion_declares_every_registered_concept_with_a_reason(lesion):
    cls = LESIONS[lesion]
    assert undeclared(cls, CONCEPT_NAMES) == [], f"{lesion} declares nothing about these concepts"
    for key, (expect, why) in cls.declares.items():
        assert expect in EXPECTATIONS, (key, expect)
        assert len(why) > 20, f"{lesion}: the reason for {key} is missing"
        assert key.split("/")[0] in CONCEPT_NAMES, f"{lesion} declares an unknown concept {key}"
    assert any(e in BREAKS for e, _ in cls.declares.values()), f"{lesion} breaks nothing"


def test_a_new_concept_without_declarations_is_caught():
    class Partial(Lesion):
        name, summary = "partial", "declares one concept only"
        declares = {"gravity": ("fail", "a reason long enough to pass the length check")}

    assert undeclared(Partial, ["gravity", "newconcept"]) == ["newconcept"]


def test_lesion_controls_carry_the_registry_declarations_and_no_pass_default():
    ctrls = {c.name: c for c in lesion_controls()}
    assert set(ctrls) == {"oracle-intact", *(f"oracle-{n}" for n in LESIONS)}
    nsm = ctrls["oracle-no-shape-memory"]
    assert nsm.expectation("Unchangeableness-v2", "occluded") == "fail"
    assert nsm.expectation("Unchangeableness-v2", "visible") == "pass"
    assert nsm.expectation("Unchangeableness-v2") == "none"
    assert nsm.expectation("SomeUserConcept-v1") == "none"  # no silent pass
    assert "unchangeableness/occluded: fail" in nsm.why


def test_unknown_lesion_is_refused_with_the_known_names():
    with pytest.raises(UnknownNameError, match="unknown lesion 'no-friction' .*no-gravity"):
        LesionedOracle("no-friction")
    assert get_lesion("energy-gain").oracle_args({})["elasticity"][-1] == pytest.approx(1.8)


def _broken(lesion: str) -> list[tuple[str, str | None]]:
    """(concept id, condition or None) that ``lesion`` declares it breaks."""
    out = []
    for cid in CONCEPTS.ids():
        base = cid.split("-v")[0].lower()
        for key, (expect, _) in LESIONS[lesion].declares.items():
            if expect in BREAKS and key.split("/")[0] == base:
                out.append((cid, key.split("/")[1] if "/" in key else None))
    return out


@pytest.fixture(scope="module")
def setting(tmp_path_factory) -> tuple[Path, object]:
    root = tmp_path_factory.mktemp("lesions")
    concepts = sorted({c for lesion in LESIONS for c, _ in _broken(lesion)})
    generate_probe_set(root / "probes", concepts, 8, 1, SimConfig(size=32))
    generate_world(root / "world", 40, 1, SimConfig(size=32))
    ws = load_probe_set(root / "world")
    return root, ws.batch(list(ws.index.clip_id))


def _accuracy(model, root: Path, calib, concept: str, condition: str | None) -> float:
    model.calibrate(calib)
    out = root / f"run-{model.name}"
    if not out.exists():
        score_probe_set(model, root / "probes", out)
    sets = set_table(load_run(out))
    sets = sets[sets["concept"] == concept]
    if condition is not None:
        sets = sets[sets["visible_violation"] == (condition == "visible")]
    else:  # a concept-level claim is about the sets that carry its verdict, as in the matrix
        sets = sets[sets["carries_verdict"].astype(bool)]
    return float(sets["accuracy"].mean())


@pytest.mark.slow
@pytest.mark.parametrize("lesion", list(LESIONS))
def test_lesion_breaks_what_it_declares(lesion, setting):
    root, calib = setting
    for concept, condition in _broken(lesion):
        intact = _accuracy(PhysicsOracle(), root, calib, concept, condition)
        lesioned = _accuracy(LesionedOracle(lesion), root, calib, concept, condition)
        assert intact >= 0.75, f"intact oracle only {intact:.2f} on {concept} {condition or ''}"
        assert lesioned <= intact - 0.25, f"{lesion}: {lesioned:.2f} vs intact {intact:.2f} on {concept}"
