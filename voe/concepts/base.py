"""The template every concept follows: sample parameters, build the scene, apply the violation.

Why: all eight concepts share the same obligations (deterministic seeding, balanced conditions,
stable slots, distractors, onset bookkeeping, splicing, validation), so the public
``Concept.make_set`` does them once and each concept fills in two hooks:

* ``_sample(rng, ctx) -> dict``: concept-specific parameters (JSON-able), drawn from the ranges
  in ``probes/<name>/spec.yaml``;
* either ``_possible_pair(params, ctx) -> (A, B, mask)`` for spliced quadruplets, or
  ``_pair(params, ctx) -> (possible, impossible, onset)`` for the pair fallback and for mirrored
  pairs (the pair and its left-right mirror, ``voe.concepts.mirror``: 2 + 2 clips).

Splicing (IntPhys, Physical Concepts): with two possible clips A and B and a time mask ``m``, the
impossible clips are ``AB[t] = B[t] if m[t] else A[t]`` and ``BA`` its complement. The impossible
pair therefore holds exactly the frames of the possible pair, so no single frame gives the answer
away; a frame-only scorer is at exactly chance.
"""

from __future__ import annotations

import hashlib
import json
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any, ClassVar, Literal

import numpy as np
import yaml

from voe.concepts.mirror import mirror, to_grid
from voe.errors import ConceptError, ProbeSetError
from voe.sim.rollout import Recording
from voe.sim.scene import Body, Scene, Segment, SimConfig

PROBES_DIR = Path(__file__).resolve().parents[2] / "probes"

#: The distractor lane: a shelf high in the scene, with end stops, that the main event never uses.
LANE_Y = 7.6
LANE_X = (0.4, 9.6)


@dataclass
class Clip:
    """One clip of a matched set."""

    variant: str  # 'A', 'B', 'AB', 'BA' (quadruplet), 'possible', 'impossible' (pair; a mirrored
    # pair adds 'mirror-possible', 'mirror-impossible')
    role: Literal["possible", "impossible"]
    rec: Recording
    onset: int


@dataclass
class MatchedSet:
    """Two possible and two impossible clips (or a possible/impossible pair)."""

    concept: str
    set_index: int
    seed: int
    kind: Literal["quadruplet", "pair", "mirrored"]
    visible: bool
    n_distractors: int
    params: dict[str, Any]
    clips: list[Clip] = field(default_factory=list)
    condition: str = ""  # "visible", "occluded" or "perceptual" (see ``Concept.conditions``)
    carries_verdict: bool = True  # False for a perceptual condition
    balance_claim: str = ""  # what the concept claims this condition reaches (``voe.io.balance``)
    confounded: bool = False  # the concept has no balanced design (``Concept.confounded``)


@dataclass(frozen=True)
class Context:
    """What the base class decides for a set before the concept samples its own parameters."""

    cfg: SimConfig
    visible: bool
    n_distractors: int
    slots: tuple[int, ...]  # a random permutation of range(K): main objects first
    distractors: tuple[Body, ...]
    lane: tuple[Segment, ...]

    @property
    def pixel(self) -> float:
        """Scene units per pixel at this probe set's resolution."""
        return 10.0 / self.cfg.size


def splice(a: Recording, b: Recording, mask: np.ndarray) -> tuple[Recording, Recording]:
    """Build the impossible pair ``(AB, BA)`` from two possible clips and a time mask ``(T,)``."""

    def mix(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        m = mask.reshape((-1,) + (1,) * (x.ndim - 1))
        return np.where(m, y, x)

    ab = Recording(mix(a.frames, b.frames), mix(a.states, b.states), mix(a.present, b.present),
                   mix(a.exists, b.exists), a.geometry)
    ba = Recording(mix(b.frames, a.frames), mix(b.states, a.states), mix(b.present, a.present),
                   mix(b.exists, a.exists), a.geometry)
    return ab, ba


def stable_seed(*parts: Any) -> np.random.SeedSequence:
    """A seed sequence from arbitrary parts, independent of Python's hash randomisation."""
    digest = hashlib.sha256(json.dumps(parts, sort_keys=True).encode()).digest()
    return np.random.SeedSequence(int.from_bytes(digest[:16], "little"))


class Concept(ABC):
    """Base class; subclasses set the class attributes and implement the hooks."""

    name: ClassVar[str]  # folder name under probes/, e.g. "permanence"
    version: ClassVar[int] = 1
    #: "mirrored": a pair whose set also holds both clips' left-right mirrors, for designs in which
    #: the impossible clip moves the other way (``voe.concepts.mirror``).
    kind: ClassVar[Literal["quadruplet", "pair", "mirrored"]] = "quadruplet"
    n_main: ClassVar[int] = 1  # slots used by the main event
    #: Condition names of visible and of occluded sets. A condition named "perceptual" (a violation
    #: in plain view that a change detector also sees) is kept and labelled, but does not carry the
    #: concept's verdict.
    conditions: ClassVar[tuple[str, str]] = ("visible", "occluded")
    #: Balance each condition reaches by design (``voe.io.balance``: "F+M+T2+P+V+H+D"), checked by
    #: ``check_concept`` and, on the stored bytes, by ``voe probes validate``.
    balance: ClassVar[dict[str, str]] = {}
    #: True when no design balances the conditions that carry the verdict: reports mark every verdict
    #: on this concept confounded (the concept's ``probes/<name>/README.md`` says why).
    confounded: ClassVar[bool] = False

    @property
    def id(self) -> str:
        return f"{self.name.capitalize()}-v{self.version}"

    def condition(self, visible: bool) -> str:
        """The condition name of a visible or occluded set."""
        return self.conditions[0] if visible else self.conditions[1]

    @cached_property
    def spec(self) -> dict[str, Any]:
        """The concept's ``spec.yaml`` (which ranges to draw from; no logic)."""
        path = PROBES_DIR / self.name / "spec.yaml"
        if not path.exists():
            raise ProbeSetError(f"missing concept spec {path}; install voe from a source checkout")
        spec = yaml.safe_load(path.read_text())
        if spec.get("id") != self.id or spec.get("kind") != self.kind:
            raise ProbeSetError(f"{path}: id/kind {spec.get('id')}/{spec.get('kind')} do not match "
                                f"the code ({self.id}/{self.kind})")
        return spec

    @property
    def ranges(self) -> dict[str, Any]:
        return self.spec.get("ranges", {})

    # -- public template method --------------------------------------------------------------
    def make_set(self, set_index: int, seed: int, cfg: SimConfig) -> MatchedSet:
        """Generate matched set number ``set_index`` of a probe set drawn with ``seed``.

        Conditions are balanced by construction: visibility alternates and the number of
        distractors cycles 0, 1, 2 across consecutive sets.
        """
        rng = np.random.default_rng(stable_seed("voe", self.id, seed, set_index))
        set_seed = int(rng.integers(2**31))
        visible = set_index % 2 == 0
        n_distractors = (set_index // 2) % 3
        slots = tuple(int(s) for s in rng.permutation(cfg.n_slots))
        if self.n_main + n_distractors > cfg.n_slots:
            raise ConceptError(f"{self.id}: {self.n_main}+{n_distractors} objects exceed {cfg.n_slots} slots")
        distractors = self._distractors(rng, n_distractors, slots[self.n_main:])
        ctx = Context(cfg, visible, n_distractors, slots, distractors, self._lane(n_distractors))
        cond = self.condition(visible)
        for attempt in range(self.MAX_DRAWS):  # noqa: B007 (read after the loop)
            params = self._sample(rng, ctx)
            try:
                clips = self._clips(params, ctx, set_index)
                break
            except (ValueError, ConceptError) as exc:
                last = exc  # a draw the design cannot be built from: draw again from the same stream
        else:
            raise ConceptError(f"{self.id} set {set_index} (seed {seed}): no buildable draw in "
                               f"{self.MAX_DRAWS} tries; last: {last}")
        if attempt:  # recorded only when it happened, so sets built at the first draw keep their bytes
            params = {**params, "redraws": attempt}
        mset = MatchedSet(self.id, set_index, set_seed, self.kind, visible, n_distractors, params,
                          condition=cond, carries_verdict=cond != "perceptual",
                          balance_claim=self.balance.get(cond, ""), confounded=self.confounded)
        mset.clips = clips
        mset.params = {**params, "splice_onset": mset.clips[0].onset}
        return mset

    #: How many parameter draws ``make_set`` tries before giving up. Why: the parameter ranges are
    #: wide on purpose, and a few draws (a screen too narrow for the frames a splice needs, a
    #: morph with no frame behind the screen) cannot be built; rejecting and redrawing from the
    #: set's own seeded stream keeps the set deterministic instead of failing the whole probe set.
    MAX_DRAWS: ClassVar[int] = 50

    def _clips(self, params: dict[str, Any], ctx: Context, set_index: int) -> list[Clip]:
        """The matched set's clips for one parameter draw (raises ValueError if it cannot be built)."""
        if self.kind == "quadruplet":
            a, b, mask = self._possible_pair(params, ctx)
            mask = np.asarray(mask, dtype=bool)
            if not mask.any() or mask.all():
                raise ConceptError(f"{self.id} set {set_index}: splice mask is empty or full")
            onset = int(np.argmax(mask))
            ab, ba = splice(a, b, mask)
            return [Clip("A", "possible", a, onset), Clip("B", "possible", b, onset),
                    Clip("AB", "impossible", ab, onset), Clip("BA", "impossible", ba, onset)]
        pos, imp, onset = self._pair(params, ctx)
        pair = [Clip("possible", "possible", pos, onset), Clip("impossible", "impossible", imp, onset)]
        if self.kind == "pair":
            return pair
        size = ctx.cfg.size
        pair = [Clip(c.variant, c.role, to_grid(c.rec, size), onset) for c in pair]
        return pair + [Clip(f"mirror-{c.variant}", c.role, mirror(c.rec, size), onset) for c in pair]

    # -- hooks -----------------------------------------------------------------------------------
    @abstractmethod
    def _sample(self, rng: np.random.Generator, ctx: Context) -> dict[str, Any]:
        """Draw this concept's parameters (JSON-able) from ``self.ranges``."""

    def _possible_pair(self, params: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, np.ndarray]:
        raise NotImplementedError

    def _pair(self, params: dict[str, Any], ctx: Context) -> tuple[Recording, Recording, int]:
        raise NotImplementedError

    # -- shared building blocks ------------------------------------------------------------------
    @staticmethod
    def uniform(rng: np.random.Generator, lo_hi: list[float]) -> float:
        return float(rng.uniform(lo_hi[0], lo_hi[1]))

    def random_look(self, rng: np.random.Generator, shapes=("circle", "box")) -> dict[str, Any]:
        """Shape, size and intensity of a main object, drawn from the spec's ranges."""
        shape = str(rng.choice(list(shapes)))
        size = self.uniform(rng, self.ranges.get("size", [0.7, 1.3]))
        return {"shape": shape, "width": size, "height": size,
                "intensity": self.uniform(rng, [0.65, 1.0])}

    @staticmethod
    def _lane(n_distractors: int) -> tuple[Segment, ...]:
        if n_distractors == 0:
            return ()
        x0, x1 = LANE_X
        return (Segment((x0, LANE_Y), (x1, LANE_Y), 0.08, 0.0, 1.0, "shelf"),
                Segment((x0, LANE_Y), (x0, LANE_Y + 1.4), 0.08, 0.0, 1.0, "wall"),
                Segment((x1, LANE_Y), (x1, LANE_Y + 1.4), 0.08, 0.0, 1.0, "wall"))

    @staticmethod
    def _distractors(rng: np.random.Generator, n: int, slots: tuple[int, ...]) -> tuple[Body, ...]:
        """Objects sliding in the top lane, identical in every clip of the set."""
        out = []
        lanes = np.linspace(LANE_X[0] + 1.2, LANE_X[1] - 1.2, max(n, 1) + 1)
        for i in range(n):
            size = float(rng.uniform(0.5, 0.9))
            shape = str(rng.choice(["circle", "box"]))
            x = float(rng.uniform(lanes[i] + size, lanes[i + 1] - size))
            out.append(Body(slot=slots[-1 - i], shape=shape, width=size, height=size, x=x,
                            y=LANE_Y + 0.08 + size / 2, vx=float(rng.uniform(-1.5, 1.5)),
                            friction=0.0, elasticity=1.0, intensity=float(rng.uniform(0.6, 1.0))))
        return tuple(out)

    @staticmethod
    def scene(ctx: Context, bodies: list[Body], statics: list[Segment], occluders=()) -> Scene:
        """A scene with the context's distractors and lane added."""
        return Scene(bodies=tuple(bodies) + ctx.distractors, statics=tuple(statics) + ctx.lane,
                     occluders=tuple(occluders))
