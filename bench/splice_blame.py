"""Where an interaction network's verdict on a concept's spliced quadruplets sits: which frame,
and which part of the prediction (presence, shape, or one of the nine state features).

Why (docs/models-findings.md, session 10): a random ``interaction`` network is off chance on
continuity, permanence and inertia, and the trained one prefers the impossible clip on collision
and solidity. Both are decided by the halves ``d_AB`` and ``d_BA`` (``voe.scoring.halves``), and
both sit on the one or two frames where a hidden object comes back; this says what in the
prediction made them. Per set it prints the two halves, the frame (relative to the first frame
where the impossible clip's side changes) that carries most of each, and the half split into parts
(summed over slots and frames), then per concept each part's share of sum |d| over the sets and
the share of sets in which that part alone has the half's sign, and how the two halves' signs
split over the sets. On the time-shifted splices (solidity, collision, gravity) AB's object comes
back late after A's history and BA's early after B's: a surprise that only grows with the time an
object was hidden, whatever the physics, makes ``d_AB > 0`` and ``d_BA < 0`` on every set ("late
dearer, early cheaper"), so the halves score 0.50 by construction and the sum's sign is set by
the curvature of that cost. Only a model that knows *when* the object should be back gets both.

Usage (a development probe set only)::

    python bench/splice_blame.py PROBES CONCEPT [--random SEED | --ckpt DIR] [--sets 10]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

VARIANTS = ("A", "B", "AB", "BA")


def set_parts(model, batch) -> tuple[np.ndarray, np.ndarray]:
    """Per-frame parts ``(4, T, 11)`` (slots summed) of a set's four clips, and the side ``(T,)``."""
    import torch

    from voe.models.interaction import frame_parts
    from voe.scoring.halves import ab_from_a

    model.net.eval()
    with torch.no_grad():
        parts = frame_parts(model.net, model.prepare(batch)).sum(2).numpy()  # (4, T, 11)
    side = ab_from_a(dict(zip(VARIANTS, batch.states, strict=True)), dict(zip(VARIANTS, batch.present, strict=True)))
    return parts, side


def half_parts(parts: np.ndarray, from_a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(2, T, 11)``: per frame and part, AB minus the possible clip showing its frame, and BA
    likewise (``voe.scoring.halves.halves`` before summing; frame 0, never scored, is 0)."""
    a, b, ab, ba = parts
    fa = from_a[:, None]
    return np.stack([ab - np.where(fa, a, b), ba - np.where(fa, b, a)])


def main() -> None:
    from voe.io.probeset import load_probe_set
    from voe.models.interaction import PARTS
    from voe.models.loading import load_model

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("probes", type=Path)
    ap.add_argument("concept", help="concept name, e.g. permanence")
    who = ap.add_mutually_exclusive_group(required=True)
    who.add_argument("--random", type=int, help="seed of a random network (the validity control)")
    who.add_argument("--ckpt", type=Path, help="a trained checkpoint directory")
    ap.add_argument("--arch", default="interaction")
    ap.add_argument("--sets", type=int, default=10)
    a = ap.parse_args()
    if a.ckpt is not None:
        model = load_model(a.arch, None, a.ckpt)
    else:
        from voe.controls.random_nets import random_network

        model = random_network(a.arch, a.random)
    ps = load_probe_set(a.probes)
    idx = ps.index
    sel = idx[(idx.concept_name == a.concept) & idx.carries_verdict]
    if sel.empty:
        raise SystemExit(f"splice_blame: no verdict sets of concept {a.concept!r} in {a.probes}")
    rows = []
    print(f"{model.name} on {a.concept} ({a.probes}); parts over |d| > 0.005 nats")
    for sid, g in list(sel.groupby("set_id"))[: a.sets]:
        ids = dict(zip(g.variant, g.clip_id, strict=True))
        parts, side = set_parts(model, ps.batch([ids[v] for v in VARIANTS]))
        h = half_parts(parts, side)  # (2, T, 11)
        start = int(np.flatnonzero(side != side[0])[0]) if (side != side[0]).any() else 0
        for name, hh in zip(("AB", "BA"), h, strict=True):
            per_frame, per_part = hh.sum(1), hh.sum(0)  # (T,), (11,)
            t = int(np.argmax(np.abs(per_frame)))
            rows.append(per_part)
            big = ", ".join(f"{p} {v:+.3f}" for p, v in zip(PARTS, per_part, strict=True) if abs(v) > 0.005)
            print(f"  {sid} d_{name} {per_part.sum():+8.3f}: frame {t - start:+d} from the splice "
                  f"({per_frame[t]:+.3f}); {big or 'nothing above 0.005'}")
    r = np.array(rows)  # (2 sets, 11)
    d = r.sum(1, keepdims=True)
    share = np.abs(r).sum(0) / max(np.abs(r).sum(), 1e-12)
    alone = (np.sign(r) == np.sign(d)) & (np.abs(r) > 0.5 * np.abs(d))
    print("  share of sum |d| by part: " + ", ".join(f"{p} {s:.2f}" for p, s in zip(PARTS, share, strict=True) if s >= 0.01))
    h = r.sum(1).reshape(-1, 2)  # (sets, 2): d_AB, d_BA
    split = {"both right": (h[:, 0] > 0) & (h[:, 1] > 0), "late dearer, early cheaper": (h[:, 0] > 0) & (h[:, 1] < 0),
             "late cheaper, early dearer": (h[:, 0] < 0) & (h[:, 1] > 0), "both wrong": (h[:, 0] < 0) & (h[:, 1] < 0)}
    print(f"  signs of (d_AB, d_BA) over {len(h)} sets: " + ", ".join(f"{k} {v.mean():.2f}" for k, v in split.items()))
    print("  halves carried (> half of d, same sign) by: "
          + ", ".join(f"{p} {c:.2f}" for p, c in zip(PARTS, alone.mean(0), strict=True) if c > 0))


if __name__ == "__main__":
    main()
