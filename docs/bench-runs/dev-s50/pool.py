"""Pool the target lines of finished untouched gap bench runs (Clopper-Pearson 95 % intervals).

    python pool.py ../gap_bench_s36_seed8367.txt ../gap_bench_s41_seed6219.txt ...

Reads only each run's summary lines (as the bench printed them), never its cases.
"""
from __future__ import annotations

import re
import sys

from scipy.stats import beta

LINES = {
    "singles": (r"^single-effect identification .*?: (\d+)/(\d+) =", None),
    "compounds": (r"^compound truths, both effects named: (\d+)/(\d+) =", None),
    "ool misnamed": (r"^out-of-library truths: misnamed as a library effect (\d+)/(\d+)", None),
    "ool rest right": (r"unexplained and located (\d+)/(\d+)", "out-of-library truths"),
    "FD coloured": (r"^false discovery on clean \(coloured noise\): (\d+)/(\d+)", None),
    "FD white": (r"^false discovery on clean \(white noise\): (\d+)/(\d+)", None),
    "coverage": (r"^95 % intervals containing the true parameters: (\d+)/(\d+)", None),
}


def cp(k: int, n: int) -> tuple[float, float]:
    """Exact (Clopper-Pearson) 95 % interval for k successes of n."""
    lo = 0.0 if k == 0 else beta.ppf(0.025, k, n - k + 1)
    hi = 1.0 if k == n else beta.ppf(0.975, k + 1, n - k)
    return lo, hi


def main(paths: list[str]) -> None:
    tot = {k: [0, 0] for k in LINES}
    for p in paths:
        text = open(p).read().split("\n")
        for key, (pat, must) in LINES.items():
            hits = [m for ln in text if (must is None or ln.startswith(must)) for m in [re.search(pat, ln)] if m]
            if len(hits) != 1:
                sys.exit(f"pool: {p}: {key!r} line found {len(hits)} times")
            tot[key][0] += int(hits[0].group(1))
            tot[key][1] += int(hits[0].group(2))
    for key, (k, n) in tot.items():
        lo, hi = cp(k, n)
        print(f"{key:15s} {k}/{n} = {100 * k / n:.1f} % (Clopper-Pearson {100 * lo:.1f}-{100 * hi:.1f} %)")


if __name__ == "__main__":
    main(sys.argv[1:])
