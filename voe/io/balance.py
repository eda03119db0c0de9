"""Which balance a matched set reaches, measured on its stored bytes.

Why: a knowledge-free scorer passes a concept whenever the possible and impossible clips differ in
something it reads (the frames, the amount of motion, the objects' heights). Each level below is
the exact condition under which one family of such scorers ties (``../shared/VALIDITY.md``):

* ``F`` frames: the multiset of frame hashes over the possible clips equals the impossible
  clips' (a per-frame scorer ties);
* ``M`` motion: the multiset of per-step change ``|x_t - x_t-1|`` (uint8 difference images) is
  equal (a motion-energy scorer ties);
* ``T<k>`` transitions: the multisets of ``(k+1)``-frame windows are equal for every window
  length up to ``k + 1`` (a scorer with at most ``k`` frames of context ties); the largest such
  ``k`` is recorded;
* state-space counterparts, over the objects a model is shown (``present``): ``P`` positions (per
  frame, every slot's x, y), ``V`` speeds (per frame, every slot's |v|), ``H`` heights (per frame,
  every slot's y) and ``D`` per-step displacement (per step, every slot's |dx|, |dy|);
* signed direction: ``X`` horizontal (per step, every slot's signed dx, and per frame, every
  slot's signed vx) and ``Y`` vertical (the same with dy, vy). ``D`` and ``V`` are blind to the
  sign, so a set whose impossible clips move left where the possible ones move right reaches
  them, and a scorer that is not mirror-symmetric (a random ConvGRU) still separates it by
  direction alone: Energy-v4 on seed 4418 (``probes/energy/README.md``). ``X`` is kept apart from
  ``Y`` because a left-right mirror balances the first in any design, while the second is, for a
  time reversal, the law itself (a ball that gains energy spends longer rising than falling).

A balance string joins the levels reached with ``+`` (``"F+M+T2+P+V+H+D+X+Y"``); ``missing``
tells which levels a concept claims that a set does not reach.
"""

from __future__ import annotations

import hashlib
import re
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

#: Levels in the order they are written; ``T`` carries its ``k``.
LEVELS = ("F", "M", "T", "P", "V", "H", "D", "X", "Y")
#: State levels, in the order they are written.
STATE_LEVELS = ("P", "V", "H", "D", "X", "Y")
#: Set kinds of two possible and two impossible clips: a spliced quadruplet (A, B, AB, BA) and a
#: mirrored pair (a pair and its left-right mirror, ``voe.concepts.mirror``).
KINDS_OF_FOUR = ("quadruplet", "mirrored")
#: The longest window checked (``T_k`` for ``k`` up to this).
K_MAX = 8


@dataclass(frozen=True)
class ClipData:
    """The parts of one stored clip that balance is measured on."""

    frames: np.ndarray  # (T, H, W) uint8
    states: np.ndarray  # (T, K, F) float32, NaN where not present
    present: np.ndarray  # (T, K) bool


@dataclass(frozen=True)
class Balance:
    """What one matched set reaches: a flag per level and the largest ``k`` of ``T_k`` (0: none)."""

    F: bool
    M: bool
    T: int
    P: bool
    V: bool
    H: bool
    D: bool
    X: bool = False
    Y: bool = False

    def __str__(self) -> str:
        parts = [n for n in ("F", "M") if getattr(self, n)]
        parts += [f"T{self.T}"] if self.T else []
        parts += [n for n in STATE_LEVELS if getattr(self, n)]
        return "+".join(parts) or "none"


def frame_digests(frames: np.ndarray) -> list[str]:
    """sha1 of each frame of ``(T, H, W)`` frames."""
    return [hashlib.sha1(np.ascontiguousarray(f).tobytes()).hexdigest() for f in frames]


def _rows(a: np.ndarray) -> list[bytes]:
    """One key per leading index of ``a`` (``(T, ...)``): its bytes."""
    a = np.ascontiguousarray(a)
    return [r.tobytes() for r in a]


def _masked(values: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """``values (T, K, ...)`` with absent slots zeroed and the mask appended, as float64 keys."""
    v = np.where(mask.reshape(mask.shape + (1,) * (values.ndim - mask.ndim)), values, 0.0)
    v = v.astype(np.float64) + 0.0  # -0.0 -> 0.0: the same position whichever way it was reached
    return np.concatenate([v.reshape(len(v), -1), mask.reshape(len(mask), -1).astype(np.float64)], axis=1)


def _state_keys(clip: ClipData, ix: dict[str, int]) -> dict[str, list[bytes]]:
    st, pr = clip.states, clip.present  # (T, K, F), (T, K)
    xy = st[:, :, [ix["x"], ix["y"]]]  # (T, K, 2)
    speed = np.hypot(st[:, :, ix["vx"]], st[:, :, ix["vy"]])  # (T, K)
    both = pr[1:] & pr[:-1]  # (T-1, K)
    signed = xy[1:] - xy[:-1]  # (T-1, K, 2)
    keys = {"P": _rows(_masked(xy, pr)), "V": _rows(_masked(speed, pr)),
            "H": _rows(_masked(xy[:, :, 1], pr)), "D": _rows(_masked(np.abs(signed), both))}
    for name, axis, vel in (("X", 0, "vx"), ("Y", 1, "vy")):
        # one multiset of steps and velocities, tagged apart: equal iff both are equal
        keys[name] = ([b"d" + r for r in _rows(_masked(signed[:, :, axis], both))]
                      + [b"v" + r for r in _rows(_masked(st[:, :, ix[vel]], pr))])
    return keys


def _windows(digests: list[str], k: int) -> list[tuple[str, ...]]:
    return [tuple(digests[t:t + k + 1]) for t in range(len(digests) - k)]


def _equal(pos: list[list], imp: list[list]) -> bool:
    return Counter(x for c in pos for x in c) == Counter(x for c in imp for x in c)


def measure(possible: Sequence[ClipData], impossible: Sequence[ClipData],
            feature_names: Sequence[str]) -> Balance:
    """The balance one matched set reaches (possible clips against impossible clips)."""
    ix = {n: i for i, n in enumerate(feature_names)}
    dig = [[frame_digests(c.frames) for c in cs] for cs in (possible, impossible)]

    def motion(c: ClipData) -> list[str]:
        diff = np.abs(c.frames[1:].astype(np.int16) - c.frames[:-1]).astype(np.uint8)  # (T-1, H, W)
        return frame_digests(diff)

    f = _equal(*dig)
    m = _equal([motion(c) for c in possible], [motion(c) for c in impossible])
    k = 0
    while f and k < K_MAX and _equal([_windows(d, k + 1) for d in dig[0]], [_windows(d, k + 1) for d in dig[1]]):
        k += 1
    keys = [[_state_keys(c, ix) for c in cs] for cs in (possible, impossible)]
    state = {n: _equal([kk[n] for kk in keys[0]], [kk[n] for kk in keys[1]]) for n in STATE_LEVELS}
    return Balance(F=f, M=m, T=k, **state)


_PLAIN = [n for n in LEVELS if n != "T"]  # levels written without a number
_TOKEN = re.compile(rf"^({'|'.join(_PLAIN)}|T(\d+))$")


def parse_claim(claim: str) -> dict[str, int]:
    """``"F+M+T2"`` -> ``{"F": 1, "M": 1, "T": 2}``; the empty string claims nothing.

    Raises:
        ValueError: an unknown level.
    """
    out: dict[str, int] = {}
    for tok in filter(None, (t.strip() for t in claim.split("+"))):
        mt = _TOKEN.match(tok)
        if not mt:
            raise ValueError(f"unknown balance level {tok!r} in {claim!r} (levels: {', '.join(n if n != 'T' else 'T<k>' for n in LEVELS)})")
        out["T" if mt.group(2) else tok] = int(mt.group(2)) if mt.group(2) else 1
    return out


def missing(reached: Balance, claim: str) -> list[str]:
    """Levels ``claim`` names that ``reached`` does not reach (empty: the claim holds)."""
    out = []
    for level, need in parse_claim(claim).items():
        have = reached.T if level == "T" else int(getattr(reached, level))
        if have < need:
            out.append(f"T{need}" if level == "T" else level)
    return out


def quadruplet_problem(possible: Sequence[np.ndarray], impossible: Sequence[np.ndarray]) -> str | None:
    """None if the impossible clips hold exactly the possible clips' frames, else a reason."""
    pos = Counter(d for f in possible for d in frame_digests(f))
    imp = Counter(d for f in impossible for d in frame_digests(f))
    if pos != imp:
        n = sum(((pos - imp) + (imp - pos)).values())
        return f"frame multisets differ ({n} unmatched frames)"
    return duplicate_problem(possible, impossible)


def duplicate_problem(possible: Sequence[np.ndarray], impossible: Sequence[np.ndarray]) -> str | None:
    """None unless an impossible clip is byte-identical to a possible one (then nothing is tested)."""
    for p in possible:
        if any(np.array_equal(p, i) for i in impossible):
            return "an impossible clip is identical to a possible clip"
    return None


def pair_problem(possible: np.ndarray, impossible: np.ndarray, onset: int) -> str | None:
    """None if the pair shares every frame before ``onset`` and differs from it on, else a reason."""
    if not np.array_equal(possible[:onset], impossible[:onset]):
        first = int(np.argmax([not np.array_equal(a, b) for a, b in zip(possible, impossible, strict=True)]))
        return f"frames differ before the onset (first at {first}, onset {onset})"
    if np.array_equal(possible[onset:], impossible[onset:]):
        return "the impossible clip never differs from the possible one"
    return None


def set_problems(kind: str, claim: str, possible: Sequence[ClipData], impossible: Sequence[ClipData],
                 onset: int, feature_names: Sequence[str]) -> tuple[Balance | None, list[str]]:
    """Measure one matched set and list what is wrong with it (empty: it keeps its promises).

    A set must have its kind's clips (2 + 2 for a quadruplet or a mirrored pair, 1 + 1 for a
    pair), no impossible clip may copy a possible one, a pair that claims no frame balance must at
    least share every frame before its onset (the branch design), and the set must reach every
    level its concept claims.
    """
    want = 2 if kind in KINDS_OF_FOUR else 1
    if not len(possible) == want == len(impossible):
        return None, [f"{kind} set with {len(possible)} possible and {len(impossible)} impossible clips"]
    problems = []
    why = duplicate_problem([c.frames for c in possible], [c.frames for c in impossible])
    if why is None and kind == "pair" and "F" not in parse_claim(claim):
        why = pair_problem(possible[0].frames, impossible[0].frames, onset)
    if why:
        problems.append(why)
    reached = measure(possible, impossible, feature_names)
    lack = missing(reached, claim)
    if lack:
        problems.append(f"claims {claim} but reaches {reached} (lacks {'+'.join(lack)})")
    return reached, problems
