"""Frame-balance checks shared by ``voe probes validate`` and ``check_concept``.

Why: the promise of a spliced quadruplet is that the impossible pair holds exactly the frames of
the possible pair, so that no single frame gives the answer away. For the pair fallback the
promise is weaker: both clips share every frame before the onset. Both are checked on the stored
bytes, not on how the set was built.
"""

from __future__ import annotations

import hashlib
from collections import Counter
from collections.abc import Sequence

import numpy as np


def frame_digests(frames: np.ndarray) -> list[str]:
    """sha1 of each frame of ``(T, H, W)`` frames."""
    return [hashlib.sha1(np.ascontiguousarray(f).tobytes()).hexdigest() for f in frames]


def quadruplet_problem(possible: Sequence[np.ndarray], impossible: Sequence[np.ndarray]) -> str | None:
    """None if the impossible clips hold exactly the possible clips' frames, else a reason."""
    pos = Counter(d for f in possible for d in frame_digests(f))
    imp = Counter(d for f in impossible for d in frame_digests(f))
    if pos != imp:
        n = sum(((pos - imp) + (imp - pos)).values())
        return f"frame multisets differ ({n} unmatched frames)"
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
