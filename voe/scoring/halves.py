"""Both halves of a spliced quadruplet: each impossible clip against the possible clip that shows
the same frame at each time step.

Why: a quadruplet's score is ``S(AB) + S(BA) - S(A) - S(B)``. Where AB shows A's frames (or B's),
the two clips differ only in what came before, so the sum splits exactly into two memory tests,
``d_AB = sum_t [s_AB(t) - s_src(t)]`` and ``d_BA`` likewise, ``src`` being the possible clip whose
frame the impossible one shows at ``t``. A model that knows the law is surprised by *both*
violations (the ball that hung in the air and the one that came back too early). A model whose
surprise only grows (or only falls) with the time an object was hidden gives the halves opposite
signs, and the sum's sign is then set by the curvature of that memory, not by physics: on
development seed 0 the pixel model's collision sum was right on every set with no set where both
halves were (docs/models-findings.md). The verdict therefore also asks each half to be right
(``voe.scoring.verdict.with_halves``). Each half compares identical frames, so every statistic of
the frames or their steps ties on it exactly, as on the sum.

Frames are matched on the stored states (equal where present, absent alike), so this needs no
knowledge of how a concept splices; where both possible clips show the same frame the side is
carried over from the frame before (splices are contiguous runs), and BA's side is always the
complement of AB's.
"""

from __future__ import annotations

import numpy as np

VARIANTS = ("A", "B", "AB", "BA")


def _same(x: np.ndarray, px: np.ndarray, y: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Per frame ``(T,)``: two clips' states ``(T, K, F)`` with presence ``(T, K)`` agree."""
    both = px & py  # (T, K)
    eq = np.where(both[..., None], np.isclose(np.nan_to_num(x), np.nan_to_num(y), atol=1e-6), True)
    return (px == py).all(1) & eq.all((1, 2))


def ab_from_a(states: dict[str, np.ndarray], present: dict[str, np.ndarray]) -> np.ndarray:
    """``(T,)`` True where AB shows A's frame (BA then shows B's), False where it shows B's."""
    sa = _same(states["AB"], present["AB"], states["A"], present["A"])
    sb = _same(states["AB"], present["AB"], states["B"], present["B"])
    out = np.empty(len(sa), dtype=bool)
    side = True  # a clip starts as its first letter says
    for t, (a, b) in enumerate(zip(sa, sb, strict=True)):
        if a != b:
            side = bool(a)
        out[t] = side
    return out


def halves(nll: dict[str, np.ndarray], from_a: np.ndarray) -> tuple[float, float]:
    """``(d_AB, d_BA)`` from per-frame surprise ``(T,)`` of A, B, AB, BA; frames not scored in
    every clip (NaN anywhere) are dropped, as for the sum (``voe.scoring.metrics.score_set``)."""
    keep = ~np.isnan(np.stack([nll[v] for v in VARIANTS])).any(0)  # (T,)
    n = {k: np.asarray(v, float)[keep] for k, v in nll.items()}
    fa = from_a[keep]
    d_ab = float(np.sum(n["AB"] - np.where(fa, n["A"], n["B"])))
    d_ba = float(np.sum(n["BA"] - np.where(fa, n["B"], n["A"])))
    return d_ab, d_ba


def half_score(d: float, scale: float, atol: float, rtol: float) -> float:
    """1, 0.5 or 0 as the half ``d`` is positive, a tie, or negative (tolerances as for the sum,
    relative to ``scale``, the summed absolute surprise of the clips involved)."""
    if abs(d) <= rtol * scale + atol:
        return 0.5
    return 1.0 if d > 0 else 0.0


def quadruplet_halves(nll: dict[str, np.ndarray], from_a: np.ndarray, atol: float, rtol: float) -> float:
    """A quadruplet's halves accuracy: the mean of its two half scores (0, 0.25, ..., 1), from
    per-frame surprise ``(T,)`` per variant and the splice side ``from_a`` ``(T,)``."""
    d_ab, d_ba = halves(nll, from_a)
    scale = float(sum(np.nansum(np.abs(v)) for v in nll.values()))
    return 0.5 * (half_score(d_ab, scale, atol, rtol) + half_score(d_ba, scale, atol, rtol))


_SIDES: dict[str, dict[str, np.ndarray]] = {}


def cached_sides(manifest_sha256: str) -> dict[str, np.ndarray] | None:
    """The sides ``splice_sides`` already read for that probe set, else ``None`` (no I/O)."""
    return _SIDES.get(manifest_sha256)


def splice_sides(probes) -> dict[str, np.ndarray]:
    """Per quadruplet set id of a probe set (a ``ProbeSet``): ``ab_from_a`` ``(T,)``.

    Read once per probe set (keyed by its manifest sha256): every table of every run scored on it
    needs the same sides, and only states and presence are read, never frames.
    """
    key = probes.manifest_sha256
    if key not in _SIDES:
        idx = probes.index
        quads = idx[idx["variant"].isin(VARIANTS)]
        out = {}
        for sid, grp in quads.groupby("set_id", sort=True):
            ids = dict(zip(grp["variant"], grp["clip_id"], strict=True))
            if set(ids) != set(VARIANTS):
                continue
            rows = probes.rows([ids[v] for v in VARIANTS])
            st, pr = probes.array("states").read(rows), probes.array("present").read(rows)
            out[str(sid)] = ab_from_a(dict(zip(VARIANTS, st, strict=True)), dict(zip(VARIANTS, pr, strict=True)))
        _SIDES[key] = out
    return _SIDES[key]
