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


def _occluded_only(concepts: tuple[str, ...]) -> dict[str, str]:
    """Fail on the occluded half of each concept, pass on the visible half (no claim on the whole)."""
    out: dict[str, str] = {}
    for c in concepts:
        out.update({f"{c}/occluded": "fail", f"{c}/visible": "pass", c: "none"})
    return out


#: lesion -> (declared expectations, why). A lesion breaks its own concept, and also any concept
#: whose violation cannot be seen without the knocked-out law (the why says which and how); every
#: other concept it must pass. The parts marked "physically implied" were added after the first
#: matrix (README, "Validity controls"), each with its reason.
LESION_DECLARATIONS: dict[str, tuple[dict[str, str], str]] = {
    "no-gravity": ({"gravity": "fail"},
                   "expects unsupported objects to keep their velocity, so floating looks normal"),
    "no-collisions": ({"solidity": "fail", "collision": "fail"},
                      "expects objects to pass through walls, shelves and each other (the floor "
                      "still holds them)"),
    "forget-occluded": (_occluded_only(("permanence", "continuity", "unchangeableness", "inertia",
                                        "collision")),
                        "forgets what goes out of sight: vanishing is expected, reappearing is a "
                        "new object, and changes behind a screen go unnoticed; physically implied: "
                        "a collision hidden behind a screen is judged only by what comes out, and "
                        "new objects may come out going anywhere (not on the list: occluded "
                        "solidity, where the impossible object emerges where none went in, an "
                        "appearance being surprising in itself, and occluded energy, whose "
                        "impossible ball keeps gaining energy in the bounces that follow in view)"),
    "no-shape-memory": (_occluded_only(("unchangeableness",)),
                        "does not remember shape or size behind a screen (nor, therefore, when a "
                        "hidden object's edges will clear it); in plain view it sees them"),
    "no-inertia": ({"inertia": "fail", "collision": "fail"},
                   "expects objects to stop: every change of speed is as likely as none; "
                   "physically implied: a collision is an exchange of momentum, and without "
                   "inertia there is no momentum to exchange, so a bounce and a pass-through are "
                   "equally unexpected"),
    "energy-gain": ({"energy": "chance"},
                    "lets bounces gain energy as readily as lose it, so a too-high bounce is as "
                    "ordinary as a low one: chance, not reversed"),
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
