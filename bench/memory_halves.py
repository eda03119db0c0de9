"""Halves of random (or trained) object-centric networks on the occluded verdict sets of a few
concepts, without a full scoring run: the cheap check of a design's random-network control.

Why (session 15): a design change meant to make random draws forget a hidden object is falsified
by one random draw whose halves sit off chance on continuity or permanence; that needs only the
concept's 10 verdict quadruplets per draw, not the whole probe set. Per draw and concept it prints
the halves accuracy (ties as halves, the verdict statistic of the spliced concepts), the sum
accuracy, and the median |d| of the halves (the size of the memory: ties are below 0.01 nats).
OFF marks a cell the validity suite would count as off chance (bootstrap CI of the halves accuracy
without 0.5 and two-sided sign-flip p below ALPHA, ``voe.controls.confound.off_chance``): for a
random network, one such cell makes the trained architecture's verdict there *confounded*.

    python bench/memory_halves.py PROBES --arch interaction-v3 --seeds 10 continuity permanence
    python bench/memory_halves.py PROBES --arch ARCH --ckpt DIR continuity permanence
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd


def main() -> None:
    from voe.controls.confound import off_chance
    from voe.controls.matrix import two_sided_pvalue
    from voe.controls.random_nets import random_network
    from voe.io.probeset import load_probe_set
    from voe.models.loading import load_model
    from voe.scoring.halves import halves, quadruplet_halves, splice_sides
    from voe.scoring.metrics import TIE_ATOL, TIE_RTOL
    from voe.scoring.stats import bootstrap_ci

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("probes", type=Path)
    ap.add_argument("concepts", nargs="+")
    ap.add_argument("--arch", default="interaction-v3")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--ckpt", type=Path, default=None)
    a = ap.parse_args()
    ps = load_probe_set(a.probes)
    idx = ps.index
    sides = splice_sides(ps)
    models = ([load_model(a.arch, None, a.ckpt)] if a.ckpt else
              [random_network(a.arch, s) for s in range(a.seeds)])
    for c in a.concepts:
        q = idx[(idx.concept_name == c) & idx.carries_verdict.astype(bool) & (idx.set_kind == "quadruplet")]
        ids = list(q.clip_id)
        if not ids:
            print(f"{c:16s} no spliced quadruplets carry its verdict (skipped)")
            continue
        b = ps.batch(ids)
        for i, m in enumerate(models):
            nll = m.frame_nll(b)  # (B, T)
            per = dict(zip(ids, nll, strict=True))
            hv, sm, dd = [], [], []
            for sid, g in q.groupby("set_id", sort=True):
                n = {v: per[cid] for v, cid in zip(g.variant, g.clip_id, strict=True)}
                hv.append(quadruplet_halves(n, sides[str(sid)], TIE_ATOL, TIE_RTOL))
                d_ab, d_ba = halves(n, sides[str(sid)])
                sm.append(1.0 if d_ab + d_ba > TIE_ATOL else 0.5 if abs(d_ab + d_ba) <= TIE_ATOL else 0.0)
                dd += [abs(d_ab), abs(d_ba)]
            name = a.ckpt.name if a.ckpt else f"s{i}"
            lo, hi = bootstrap_ci(np.array(hv))
            cell = pd.DataFrame({"ci_low": [lo], "ci_high": [hi], "p_two_sided": [two_sided_pvalue(np.array(hv))]})
            off = bool(off_chance(cell).iloc[0])  # the suite's own rule, not a copy
            print(f"{c:16s} {name:10s} halves {np.mean(hv):.2f} [{lo:.2f}, {hi:.2f}]{' OFF' if off else '    '}"
                  f"  sum {np.mean(sm):.2f}  "
                  f"median |d| {np.median(dd):.4f}  max |d| {np.max(dd):.4f}  (sets {len(hv)})", flush=True)


if __name__ == "__main__":
    main()
