"""Peak memory of ``voe world generate`` and ``voe train`` at two world sizes (issue 13, part 6).

Why: storage and training stream in shards, so peak memory should not grow with the number of
clips. Each command runs in its own child process and its peak resident set size is read from
``os.wait4`` (the largest process of the child's tree, workers included). The reference measured
in the same run is the peak RSS of a child that only imports what ``voe train`` imports (the
interpreter, numpy, pandas, torch): the floor no streaming can go below. The figure to read is
the ratio larger/smaller (target <= 1.5x).

    nice -n 10 python bench/memory_bench.py --small 1000 --large 16000 --jobs 1 --steps 20

Before sharding, the same commands peaked at 0.65 GB (1,000 clips) and 2.1 GB (4,000 clips).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def peak_rss(cmd: list[str]) -> tuple[float, float]:
    """(peak RSS in MB of ``cmd``'s process tree, wall seconds); exits if the command fails."""
    start = time.monotonic()
    with tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(proc.pid, 0)  # this child's own rusage, its waited workers included
        proc.returncode = os.waitstatus_to_exitcode(status)
        if proc.returncode != 0:
            err.seek(0)
            raise SystemExit(f"memory_bench: {' '.join(cmd)} failed ({proc.returncode}): {err.read().strip()[-500:]}")
    return usage.ru_maxrss / 1024, time.monotonic() - start


def disk_mb(path: Path) -> float:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file()) / 2**20


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", type=int, default=1000, help="clips in the smaller world")
    ap.add_argument("--large", type=int, default=16000, help="clips in the larger world")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes of world generation")
    ap.add_argument("--steps", type=int, default=20, help="training steps (fixed, so time does not dominate)")
    ap.add_argument("--model", default="interaction", help="model to train")
    ap.add_argument("--work", type=Path, default=None, help="keep the worlds here (default: a temp dir)")
    args = ap.parse_args()

    work = args.work or Path(tempfile.mkdtemp(prefix="voe-memory-"))
    py = [sys.executable, "-m", "voe"]
    ref, _ = peak_rss([sys.executable, "-c", "import numpy, pandas, torch, voe.io.probeset, voe.models.train"])
    rows = []
    try:
        for n in (args.small, args.large):
            world, ckpt = work / f"world-{n}", work / f"ckpt-{n}"
            gen, gen_s = peak_rss([*py, "world", "generate", "--n", str(n), "--out", str(world),
                                   "--jobs", str(args.jobs), "--seed", "0", "--overwrite"])
            tr, tr_s = peak_rss([*py, "train", args.model, "--data", str(world), "--out", str(ckpt),
                                 "--steps", str(args.steps)])
            rows.append((n, disk_mb(world), gen, gen_s, tr, tr_s))
            print(f"{n:>6} clips: on disk {rows[-1][1]:7.0f} MB | world generate peak RSS {gen:6.0f} MB "
                  f"({gen_s:5.0f} s, --jobs {args.jobs}) | train {args.model} peak RSS {tr:6.0f} MB "
                  f"({tr_s:4.0f} s, {args.steps} steps)", flush=True)
            shutil.rmtree(ckpt, ignore_errors=True)
    finally:
        if args.work is None:
            shutil.rmtree(work, ignore_errors=True)
    (n0, d0, g0, _, t0, _), (n1, d1, g1, _, t1, _) = rows
    print(f"reference: importing numpy, pandas, torch and voe peaks at {ref:.0f} MB")
    print(f"ratio {n1}/{n0} clips ({n1 / n0:.0f}x the clips, {d1 / d0:.1f}x the bytes on disk): "
          f"world generate {g1 / g0:.2f}x, train {t1 / t0:.2f}x (target <= 1.5x)")
    print(f"growth per 1,000 clips: world generate {1000 * (g1 - g0) / (n1 - n0):.1f} MB, "
          f"train {1000 * (t1 - t0) / (n1 - n0):.1f} MB (the stacked writer grew by about 500 MB)")


if __name__ == "__main__":
    main()
