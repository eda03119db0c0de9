"""Both halves of every spliced quadruplet, per run and concept (``voe.controls.splice_halves``).

For each run: per concept, over the sets that carry the verdict (the occluded splices), the share
of sets whose summed score is right (impossible pair more surprising) and the share where *each*
impossible clip is more surprising than the possible clip showing the same frames.

    python bench/splice_halves.py PROBES RUN [RUN ...]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd


def main() -> int:
    from voe.controls.splice_halves import set_halves
    from voe.io.probeset import load_probe_set

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("probes", type=Path)
    ap.add_argument("runs", type=Path, nargs="+")
    a = ap.parse_args()
    ps = load_probe_set(a.probes)
    print("run x concept: sum right / both halves right, over verdict-carrying quadruplets")
    for run in a.runs:
        missing = [f for f in ("clips.parquet", "frames.parquet") if not (run / f).exists()]
        if missing:
            print(f"error: {run} has no {missing[0]} (a run of `voe score`, which stores per-frame surprise)",
                  file=sys.stderr)
            return 2
        clips = pd.read_parquet(run / "clips.parquet")
        if "carries_verdict" in clips.columns:
            clips = clips[clips["carries_verdict"].astype(bool)]
        h = set_halves(pd.read_parquet(run / "frames.parquet"), clips, ps)
        cells = [f"{c.split('-v')[0][:8]} {g['sum_right'].mean():.2f}/{g['both_right'].mean():.2f}"
                 for c, g in h.groupby("concept", sort=True)]
        print(f"{run.name:24s} " + "  ".join(cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
