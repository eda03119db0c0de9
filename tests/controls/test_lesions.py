"""One lesion per law: each knocked-out law lowers accuracy on the concept that tests it."""

from pathlib import Path

import pytest

from voe.concepts.generate import generate_probe_set
from voe.controls.lesions import LESIONS, LesionedOracle
from voe.errors import UnknownNameError
from voe.io.probeset import load_probe_set
from voe.models.oracle import PhysicsOracle
from voe.scoring.runs import load_run
from voe.scoring.score import score_probe_set
from voe.scoring.table import set_table
from voe.sim.scene import SimConfig
from voe.world.generate import generate_world

#: lesion -> (concept, condition or None) it must degrade
LAW = {
    "no-gravity": ("Gravity-v3", None),
    "no-collisions": ("Solidity-v2", None),
    "no-inertia": ("Inertia-v1", None),
    "forget-occluded": ("Permanence-v2", False),
    "energy-gain": ("Energy-v3", None),
}


@pytest.fixture(scope="module")
def setting(tmp_path_factory) -> tuple[Path, object]:
    root = tmp_path_factory.mktemp("lesions")
    generate_probe_set(root / "probes", sorted({c for c, _ in LAW.values()}), 8, 1, SimConfig(size=32))
    generate_world(root / "world", 40, 1, SimConfig(size=32))
    ws = load_probe_set(root / "world")
    return root, ws.batch(list(ws.index.clip_id))


def _accuracy(model, root: Path, calib, concept: str, visible) -> float:
    model.calibrate(calib)
    out = root / f"run-{model.name}"
    if not out.exists():
        score_probe_set(model, root / "probes", out)
    sets = set_table(load_run(out))
    sets = sets[sets["concept"] == concept]
    if visible is not None:
        sets = sets[sets["visible_violation"] == visible]
    return float(sets["accuracy"].mean())


@pytest.mark.parametrize("lesion", sorted(LAW))
def test_lesion_breaks_its_law(lesion, setting):
    root, calib = setting
    concept, visible = LAW[lesion]
    intact = _accuracy(PhysicsOracle(), root, calib, concept, visible)
    lesioned = _accuracy(LesionedOracle(lesion), root, calib, concept, visible)
    assert intact >= 0.75, f"intact oracle only {intact:.2f} on {concept}"
    assert lesioned <= intact - 0.25, f"{lesion}: {lesioned:.2f} vs intact {intact:.2f} on {concept}"


def test_every_lesion_is_declared_and_unknown_is_refused():
    from voe.controls.builtin import LESION_DECLARATIONS

    assert set(LESION_DECLARATIONS) == set(LESIONS)
    with pytest.raises(UnknownNameError, match="unknown lesion"):
        LesionedOracle("no-friction")
