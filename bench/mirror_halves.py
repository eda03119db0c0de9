"""Does a random network's verdict on a hidden-splice concept follow the direction of motion?
Scores its halves on a concept's verdict quadruplets and on their exact left-right mirrors.

Why: a random network is off chance on continuity and permanence with one sign on every set
(docs/models-findings.md, session 10). If that sign came from a direction the probes share (objects
entering the same way, or the hidden stretch's state difference always pointing one way), a
knowledge-free odd function of the remembered state would pick it up, and the mirrored sets
(``voe.concepts.mirror``: exact on a ``2**-16`` grid, frames redrawn from the mirrored states)
would flip it; a set design holding both mirrors would then be balanced for it. If the sign
stays, the carrier is not a left-right direction and mirroring cannot balance it. Both copies
are put on the grid (``to_grid``) so that they differ only by the mirror. Halves accuracy is as
in the verdict (``voe.scoring.halves.quadruplet_halves``, ties within ``TIE_ATOL``).

Usage (a development probe set only)::

    python bench/mirror_halves.py PROBES CONCEPT [--seeds 2,4,7] [--arch interaction]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np


def set_batches(ps, concept: str):
    """Per verdict quadruplet of ``concept``: (set id, original batch, mirrored batch, side)."""
    from voe.concepts.mirror import mirror, to_grid
    from voe.io.batch import Batch
    from voe.scoring.halves import VARIANTS, ab_from_a
    from voe.sim.rollout import Recording

    idx = ps.index
    sel = idx[(idx.concept_name == concept) & idx.carries_verdict & idx.variant.isin(VARIANTS)]
    if sel.empty:
        raise SystemExit(f"mirror_halves: no verdict quadruplets of concept {concept!r} in {ps.path}")
    size = int(ps.manifest["frame_size"][0])

    def batch(recs: list[Recording]) -> Batch:
        return Batch(frames=np.stack([r.frames for r in recs]), states=np.stack([r.states for r in recs]),
                     present=np.stack([r.present for r in recs]), feature_names=ps.feature_names,
                     dt=ps.dt, geometry=tuple(r.geometry for r in recs),
                     clip_ids=tuple(f"m{i}" for i in range(len(recs))), seeds=(0,) * len(recs))

    out = []
    for sid, g in sel.groupby("set_id", sort=True):
        ids = dict(zip(g.variant, g.clip_id, strict=True))
        ids = [ids[v] for v in VARIANTS]
        d, geo = ps.get(ids), ps.batch(ids).geometry
        recs = [to_grid(Recording(d["frames"][i], d["states"][i], d["present"][i], d["exists"][i], geo[i]), size)
                for i in range(len(ids))]
        orig, mirr = batch(recs), batch([mirror(r, size) for r in recs])
        side = ab_from_a(dict(zip(VARIANTS, orig.states, strict=True)), dict(zip(VARIANTS, orig.present, strict=True)))
        out.append((str(sid), orig, mirr, side))
    return out


def main() -> None:
    from voe.controls.random_nets import random_network
    from voe.io.probeset import load_probe_set
    from voe.scoring.halves import VARIANTS, halves, quadruplet_halves
    from voe.scoring.metrics import TIE_ATOL, TIE_RTOL

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("probes", type=Path)
    ap.add_argument("concept", help="concept name, e.g. continuity")
    ap.add_argument("--seeds", default="2,4,7", help="random network seeds, comma-separated")
    ap.add_argument("--arch", default="interaction")
    a = ap.parse_args()
    sets = set_batches(load_probe_set(a.probes), a.concept)
    print(f"{a.concept} on {a.probes}: {len(sets)} verdict quadruplets, original vs mirrored")
    for seed in (int(s) for s in a.seeds.split(",")):
        model = random_network(a.arch, seed)
        acc, signs = {"original": [], "mirrored": []}, {"original": [], "mirrored": []}
        for _sid, orig, mirr, side in sets:
            for name, b in (("original", orig), ("mirrored", mirr)):
                nll = dict(zip(VARIANTS, model.frame_nll(b), strict=True))  # (T,) per variant
                acc[name].append(quadruplet_halves(nll, side, TIE_ATOL, TIE_RTOL))
                signs[name].append(np.sign(halves(nll, side)))
        kept = float(np.mean(np.array(signs["original"]) == np.array(signs["mirrored"])))
        print(f"  {model.name}: halves accuracy original {np.mean(acc['original']):.2f}, mirrored "
              f"{np.mean(acc['mirrored']):.2f}; signs of d_AB, d_BA the mirror keeps: {kept:.2f}")


if __name__ == "__main__":
    main()
