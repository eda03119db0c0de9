"""Both halves of a spliced quadruplet: is *each* impossible clip more surprising than the possible
clip that shows the same frames?

Why: a quadruplet's score is ``s(AB) + s(BA) - s(A) - s(B)``. Where AB shows A's frames (or B's),
the two clips differ only in what came before, so the sum splits exactly into two memory tests,
``d_AB = sum_t [s_AB(t) - s_src(t)]`` and ``d_BA`` likewise, ``src`` being the possible clip whose
frame the impossible one shows at ``t``. A model that knows the law is surprised by both
violations (the ball that hung in the air *and* the one that came back too early): ``d_AB > 0``
and ``d_BA > 0``. A model whose surprise only grows (or only shrinks) with the time an object was
hidden, knowing nothing of when it should come back, makes the two halves opposite in sign, and
the sum's sign is then set by the curvature of that growth, not by physics. On dev seed 4077 the
physics oracle has both halves positive on 90-100 % of the occluded sets of every suffix-spliced
concept, constant velocity on exactly the concepts it knows (inertia, permanence,
unchangeableness) and on none of gravity, solidity and collision, random ``interaction``
networks on 0-20 % (one 70 %), and the demo's pixel model on none, although its *sum* is right on
all collision sets (docs/models-findings.md).

The halves themselves live in ``voe.scoring.halves`` (how frames are matched to their side is
described there), where the verdict also uses them; this module lays them out per set for
``bench/splice_halves.py``.
"""

from __future__ import annotations

import pandas as pd

from voe.scoring.halves import halves, splice_sides


def set_halves(frames: pd.DataFrame, clips: pd.DataFrame, probes, atol: float = 0.01) -> pd.DataFrame:
    """Per quadruplet of a run (``frames``: clip_id, t, nll; ``clips``: the run's clip table) on
    ``probes`` (a ``ProbeSet``): d_AB, d_BA, whether the sum and both halves are positive."""
    rows = []
    quads = clips[clips["set_kind"] == "quadruplet"]
    nll = {cid: g.sort_values("t")["nll"].to_numpy() for cid, g in frames.groupby("clip_id")}
    sides = splice_sides(probes)
    for sid, grp in quads.groupby("set_id", sort=True):
        ids = dict(zip(grp["variant"], grp["clip_id"], strict=True))
        d_ab, d_ba = halves({v: nll[ids[v]] for v in ids}, sides[str(sid)])
        first = grp.iloc[0]
        rows.append({"concept": first["concept"], "condition": first.get("condition", ""), "set_id": sid,
                     "d_ab": d_ab, "d_ba": d_ba, "sum_right": d_ab + d_ba > atol,
                     "both_right": bool(d_ab > atol and d_ba > atol)})
    return pd.DataFrame(rows)
