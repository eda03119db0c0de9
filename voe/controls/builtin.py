"""The built-in controls and what each declares, written down before any of them is run.

Keys of ``expect`` are concept names, or ``concept/<condition>`` (``visible``, ``occluded``, ...)
for a declaration about one condition only. Declarations were chosen on the development seed
(0) and the matrix is quoted once on an untouched seed (``bench/validity_bench.py``).

Families:

* ``knowledge-free``: statistics of the stored bytes (per-frame density, motion energy, object
  height and speed) and the stress-test classifiers; they know nothing, so ``chance`` everywhere;
* ``random-net``: every learned architecture with random, non-zero weights, ``RANDOM_SEEDS``
  initialisations each; ``chance`` everywhere;
* ``physics-poor``: frame copy, constant velocity and track smoothness, each declared to know
  part of physics: ``pass`` where that knowledge suffices, ``not-learned`` everywhere else;
* ``lesion``: the physics oracle, intact and with one law knocked out (the lesion registry);
* ``counterfactual``: the object-centric model trained in a world that lacks a law.
"""

from __future__ import annotations

from voe.controls.spec import Control

LEARNED_ARCHS = ("mlp", "interaction", "pixel")
#: At least 10 initialisations per architecture (the V-JEPA study used 20).
RANDOM_SEEDS = tuple(range(10))
FAMILIES = ("knowledge-free", "random-net", "physics-poor", "lesion", "counterfactual")
CORE = ("permanence", "continuity", "unchangeableness", "solidity", "inertia", "gravity", "collision", "energy")

_STATS = {
    "density": ("F", "a per-frame pixel density: one frame at a time, no time, no physics"),
    "motion-energy": ("M", "the order-free sum of per-step change |x_t - x_t-1|: amount of motion only"),
    "height": ("S", "mean height of the visible objects: where things are, not how they may move"),
    "speed": ("S", "summed speed of the visible objects: how much moves, not whether it may"),
    "stress-frame": ("F", "a classifier of single frames, cross-validated over matched sets: whatever "
                          "one frame gives away"),
    "stress-step": ("M", "a classifier of single steps of change, cross-validated over matched sets: "
                         "whatever one step gives away"),
}


def knowledge_free_controls() -> list[Control]:
    """Statistics of the stored bytes and the stress test: chance on every concept."""
    return [Control(name=name, family="knowledge-free", model=f"stat:{name}", default="chance",
                    invariant_to=inv, why=f"knows nothing: {why}")
            for name, (inv, why) in _STATS.items()]


def random_net_controls(seeds: tuple[int, ...] = RANDOM_SEEDS) -> list[Control]:
    """Random (never trained, output layers included) networks: chance on every concept."""
    return [Control(name=f"random-{arch}-s{seed}", family="random-net",
                    model="voe.controls.random_nets:random_network", args={"arch": arch, "seed": seed},
                    default="chance", why="random weights know no physics; a random non-constant "
                                          "function of what it sees")
            for arch in LEARNED_ARCHS for seed in seeds]


def _knows(passes: dict[str, str], not_learned: dict[str, str], extra: dict[str, str] | None = None) -> dict[str, str]:
    out = {c: "pass" for c in passes}
    out.update({c: "not-learned" for c in not_learned})
    out.update(extra or {})
    return out


FRAMECOPY_WHY = ("pixels persist, so it can notice a change in plain view (perceptual conditions, "
                 "no claim) but never one behind a screen, nor one that needs a law of motion")
CONSTVEL_PASS = {
    "permanence": "hidden objects persist, carried on at constant velocity",
    "continuity": "a hidden object is carried on at constant velocity, so it is expected in the gap",
    "unchangeableness": "a hidden object persists as it was, look (shape, size) included",
    "inertia": "things keep their velocity",
}
CONSTVEL_NOT = {c: "no gravity, no collisions, no energy: a straight line through everything"
                for c in ("solidity", "gravity", "collision", "energy")}
SMOOTH_PASS = {"inertia": "a spontaneous change of speed or direction is a jolt in the track"}
SMOOTH_NOT = {
    "continuity": "voe's violation is an object missing from a visible gap on an unchanged "
                  "schedule; a track statistic knows no screens, so it sees no jolt",
    "permanence": "a track that ends or begins has no second difference",
    "unchangeableness": "reads positions only, not shapes",
    **{c: "knows no gravity, collisions or energy: only that motion is smooth"
       for c in ("solidity", "gravity", "collision", "energy")},
}


def physics_poor_controls() -> list[Control]:
    """Frame copy, constant velocity, track smoothness: pass their knowledge, learn nothing else."""
    return [
        Control(name="framecopy", family="physics-poor", model="stat:framecopy",
                expect={c: "not-learned" for c in CORE}, default="not-learned",
                why=f"frame copy: {FRAMECOPY_WHY}"),
        Control(name="constvel", family="physics-poor", model="constvel", calibrate=True,
                expect=_knows(CONSTVEL_PASS, CONSTVEL_NOT), default="none",
                why="constant velocity: inertia, and hidden objects persist; " +
                    "; ".join(f"{c}: {w}" for c, w in {**CONSTVEL_PASS, **CONSTVEL_NOT}.items())),
        Control(name="smoothness", family="physics-poor", model="stat:smoothness",
                expect=_knows(SMOOTH_PASS, SMOOTH_NOT), default="none",
                why="track smoothness (GeoPhys style): continuity and inertia as smooth motion; " +
                    "; ".join(f"{c}: {w}" for c, w in {**SMOOTH_PASS, **SMOOTH_NOT}.items())),
    ]


def lesion_controls() -> list[Control]:
    """The physics oracle, intact and with each registered law knocked out."""
    from voe.controls.lesion_registry import LESIONS

    out = [Control(name="oracle-intact", family="lesion", model="oracle", default="pass",
                   why="the intact physics oracle: should pass every concept", calibrate=True)]
    for name, cls in LESIONS.items():
        law = cls()
        out.append(Control(name=f"oracle-{name}", family="lesion",
                           model="voe.controls.lesions:LesionedOracle", args={"lesion": name},
                           expect=law.expect(), default="none", why=law.why(), calibrate=True))
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


def probe_set_controls() -> list[Control]:
    """The controls ``voe report`` computes from the probe set itself (torch-free, seconds)."""
    return [*knowledge_free_controls(), *[c for c in physics_poor_controls() if c.model.startswith("stat:")]]


def builtin_controls(families: tuple[str, ...] = FAMILIES) -> list[Control]:
    """All built-in controls of the requested families."""
    makers = {"knowledge-free": knowledge_free_controls, "random-net": random_net_controls,
              "physics-poor": physics_poor_controls, "lesion": lesion_controls,
              "counterfactual": counterfactual_controls}
    return [c for fam in families for c in makers[fam]()]
