"""The built-in controls and what each declares.

Keys of ``expect`` are concept names, or ``concept/visible`` and ``concept/occluded`` for a
declaration about one condition only (a lesion of memory behind screens, say, should break only
the occluded half of a concept and leave the visible half intact).

Every declaration here was written from the physics before the matrix was run; the README of
``voe validate-suite`` (and the demo report) shows where outcomes disagree.
"""

from __future__ import annotations

from voe.controls.spec import Control

LEARNED_ARCHS = ("mlp", "interaction", "pixel")
UNTRAINED_SEEDS = (0, 1, 2)


def _spliced_concepts() -> list[str]:
    from voe.concepts import CONCEPTS, SUITES, get_concept

    return [n for n in SUITES["core"] if get_concept(CONCEPTS.resolve(n)).kind == "quadruplet"]


def untrained_controls() -> list[Control]:
    """Random initialisations of every learned architecture: chance everywhere."""
    return [Control(name=f"untrained-{arch}-s{seed}", family="untrained", model=arch,
                    args={"seed": seed}, default="chance",
                    why="random weights know no physics: chance on every concept")
            for arch in LEARNED_ARCHS for seed in UNTRAINED_SEEDS]


def frame_only_controls() -> list[Control]:
    """Scorers that see one frame at a time: exactly chance on spliced concepts."""
    spliced = {c: "chance" for c in _spliced_concepts()}
    why = ("sees one frame at a time: exact ties on spliced quadruplets; on pair concepts the "
           "number shows how much a single frame gives away")
    return [
        Control(name="frame-only-density", family="frame-only", model="voe.controls.frame_only:PixelDensity",
                expect=spliced, default="none", why=why, calibrate=True),
        Control(name="frame-only-random-0", family="frame-only", model="voe.controls.frame_only:RandomFeatureScorer",
                args={"seed": 0}, expect=spliced, default="none", why=why),
        Control(name="frame-only-random-1", family="frame-only", model="voe.controls.frame_only:RandomFeatureScorer",
                args={"seed": 1}, expect=spliced, default="none", why=why),
    ]


#: lesion -> (declared expectations, why)
LESION_DECLARATIONS: dict[str, tuple[dict[str, str], str]] = {
    "no-gravity": ({"gravity": "fail"},
                   "expects unsupported objects to keep their velocity, so floating looks normal"),
    "no-collisions": ({"solidity": "fail", "collision": "fail"},
                      "expects objects to pass through walls, shelves and each other"),
    "forget-occluded": ({"permanence/occluded": "fail", "permanence/visible": "pass", "permanence": "none",
                         "continuity/occluded": "fail", "continuity/visible": "pass", "continuity": "none",
                         "unchangeableness/occluded": "fail", "unchangeableness/visible": "pass",
                         "unchangeableness": "none",
                         "inertia/occluded": "fail", "inertia/visible": "pass", "inertia": "none"},
                        "forgets what goes out of sight: vanishing is expected, reappearing is a "
                        "new object, and changes behind a screen go unnoticed"),
    "no-shape-memory": ({"unchangeableness": "fail"},
                        "does not remember shape or size from frame to frame"),
    "no-inertia": ({"inertia": "fail"},
                   "expects objects to stop: every change of speed is as likely as none"),
    "energy-gain": ({"energy": "fail"}, "lets bounces gain energy, so a too-high bounce looks normal"),
}


def lesion_controls() -> list[Control]:
    """The physics oracle, intact and with each law knocked out."""
    out = [Control(name="oracle-intact", family="lesion", model="oracle", default="pass",
                   why="the intact physics oracle: should pass every concept", calibrate=True)]
    for lesion, (expect, why) in LESION_DECLARATIONS.items():
        out.append(Control(name=f"oracle-{lesion}", family="lesion",
                           model="voe.controls.lesions:LesionedOracle", args={"lesion": lesion},
                           expect=expect, default="pass", why=why, calibrate=True))
    return out


def counterfactual_controls() -> list[Control]:
    """The object-centric model trained in worlds that lack a law."""
    return [
        Control(name="interaction-no-gravity-world", family="counterfactual", model="interaction",
                train_on="gravity_off", expect={"gravity": "fail"}, default="pass",
                why="trained where nothing falls: floating is normal"),
        Control(name="interaction-pass-through-world", family="counterfactual", model="interaction",
                train_on="pass_through", expect={"solidity": "fail", "collision": "fail"}, default="pass",
                why="trained where objects pass through each other"),
    ]


def builtin_controls(families: tuple[str, ...] = ("untrained", "frame-only", "lesion", "counterfactual")) -> list[Control]:
    """All built-in controls of the requested families."""
    makers = {"untrained": untrained_controls, "frame-only": frame_only_controls,
              "lesion": lesion_controls, "counterfactual": counterfactual_controls}
    return [c for fam in families for c in makers[fam]()]
