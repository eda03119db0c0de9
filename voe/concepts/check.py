"""``check_concept``: the conformance check every registered concept must pass.

Why: like Gymnasium's ``env_checker`` and scikit-learn's ``check_estimator``, one public function
states what a concept promises, and the tests run it over everything in the registry, so a new
concept (ours or a user's) is held to the same standard:

* determinism: the same (seed, set index) gives byte-identical clips;
* schema: shapes, dtypes, NaN exactly where an object is not present;
* conditions: visibility and distractor counts as the base class assigns them;
* onset: inside the clip; the impossible clips follow a possible clip up to it and differ after;
* balance: every set reaches what its concept claims for its condition (``Concept.balance``,
  measured like ``voe probes validate``); pairs that claim no frame balance share the prefix;
* physical plausibility of possible clips: objects exist throughout (nothing appears or vanishes)
  and move continuously (no jump larger than their speed allows).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from voe.concepts.base import Concept, MatchedSet
from voe.errors import ConceptError
from voe.io.balance import ClipData, set_problems
from voe.sim.scene import FEATURE_NAMES, SimConfig

_X, _Y, _VX, _VY = (FEATURE_NAMES.index(n) for n in ("x", "y", "vx", "vy"))


def _fail(c: Concept, i: int, msg: str) -> None:
    raise ConceptError(f"check_concept({c.id}) set {i}: {msg}")


def _check_schema(c: Concept, i: int, m: MatchedSet, cfg: SimConfig) -> None:
    T, K, F, S = cfg.n_frames, cfg.n_slots, len(FEATURE_NAMES), cfg.size
    for clip in m.clips:
        r = clip.rec
        if r.frames.shape != (T, S, S) or r.frames.dtype != np.uint8:
            _fail(c, i, f"{clip.variant} frames {r.frames.dtype}{r.frames.shape}")
        if r.states.shape != (T, K, F) or r.states.dtype != np.float32:
            _fail(c, i, f"{clip.variant} states {r.states.dtype}{r.states.shape}")
        if r.present.shape != (T, K) or r.exists.shape != (T, K):
            _fail(c, i, f"{clip.variant} present/exists shape {r.present.shape}")
        if (np.isnan(r.states).all(-1) != ~r.present).any():
            _fail(c, i, f"{clip.variant}: NaN states do not match present")
        if (r.present & ~r.exists).any():
            _fail(c, i, f"{clip.variant}: an object is present but does not exist")
        if not 1 <= clip.onset < T - 1:
            _fail(c, i, f"{clip.variant}: onset {clip.onset} outside [1, {T - 1})")


def _check_balance(c: Concept, i: int, m: MatchedSet, cfg: SimConfig) -> None:
    """The set reaches the balance its concept claims for its condition (as validate measures it)."""
    clips = {role: [ClipData(cl.rec.frames, cl.rec.states, cl.rec.present) for cl in m.clips if cl.role == role]
             for role in ("possible", "impossible")}
    _, why = set_problems(m.kind, m.balance_claim, clips["possible"], clips["impossible"],
                          m.clips[0].onset, FEATURE_NAMES)
    if why:
        _fail(c, i, f"{m.condition}: {why[0]}")
    if m.kind == "quadruplet" and not np.array_equal(m.clips[2].rec.frames[:m.clips[0].onset],
                                                    m.clips[0].rec.frames[:m.clips[0].onset]):
        _fail(c, i, "AB does not follow A before the onset")


def _check_declarations(c: Concept) -> None:
    """Conditions are named, their claims parse, and only a perceptual condition drops the verdict."""
    from voe.io.balance import parse_claim

    if len(c.conditions) != 2 or len(set(c.conditions)) != 2:
        raise ConceptError(f"check_concept({c.id}): conditions {c.conditions!r} must name the visible and "
                           "the occluded condition")
    for cond, claim in c.balance.items():
        if cond not in c.conditions:
            raise ConceptError(f"check_concept({c.id}): balance declared for unknown condition {cond!r}")
        try:
            parse_claim(claim)
        except ValueError as exc:
            raise ConceptError(f"check_concept({c.id}): {exc}") from exc


def _check_plausible(c: Concept, i: int, m: MatchedSet, cfg: SimConfig) -> None:
    for clip in m.clips:
        if clip.role != "possible":
            continue
        ex = clip.rec.exists  # (T, K)
        if (ex != ex[:1]).any():
            _fail(c, i, f"possible clip {clip.variant}: an object appears or vanishes")
        st = clip.rec.states  # (T, K, F)
        both = clip.rec.present[1:] & clip.rec.present[:-1]  # (T-1, K)
        step = np.hypot(*(st[1:, :, [_X, _Y]] - st[:-1, :, [_X, _Y]]).transpose(2, 0, 1))
        speed = np.maximum(np.hypot(st[1:, :, _VX], st[1:, :, _VY]),
                           np.hypot(st[:-1, :, _VX], st[:-1, :, _VY]))
        jump = both & (step > 1.5 * speed * cfg.dt + 0.05)
        if jump.any():
            t, k = np.argwhere(jump)[0]
            _fail(c, i, f"possible clip {clip.variant}: slot {k} jumps {step[t, k]:.3f} at frame {t + 1}")


def check_concept(concept: Concept, n_sets: int = 6, seed: int | Sequence[int] = 0,
                  cfg: SimConfig | None = None) -> None:
    """Run every conformance check on ``n_sets`` matched sets of each seed; raises ``ConceptError``.

    Args:
        seed: one seed or several: a concept's balance claims must hold on every set of each.
    """
    cfg = cfg or SimConfig()
    _check_declarations(concept)
    for s in ([seed] if isinstance(seed, int) else list(seed)):
        for i in range(n_sets):
            _check_set(concept, i, s, cfg)


def _check_set(concept: Concept, i: int, seed: int, cfg: SimConfig) -> None:
    m = concept.make_set(i, seed, cfg)
    again = concept.make_set(i, seed, cfg)
    for a, b in zip(m.clips, again.clips, strict=True):
        if not (np.array_equal(a.rec.frames, b.rec.frames)
                and np.array_equal(a.rec.states, b.rec.states, equal_nan=True)):
            _fail(concept, i, f"clip {a.variant} is not deterministic")
    if m.visible != (i % 2 == 0) or m.n_distractors != (i // 2) % 3:
        _fail(concept, i, "conditions are not the ones the base class assigned")
    _check_schema(concept, i, m, cfg)
    _check_balance(concept, i, m, cfg)
    _check_plausible(concept, i, m, cfg)
