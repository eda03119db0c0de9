"""Scoring throughput of the interaction model: one process vs 2 torchrun ranks (gloo, CPU).

Prints frames per second of the scoring loop (``wall_time_s`` in ``run.json``: from the first
batch to the last rank's last batch) and end to end (process start to run written, which adds
torch start-up per rank and rank 0's merge), for ``voe score`` in one process (the reference,
measured in the same run) and under ``torchrun --nproc_per_node 2``, and checks that both runs'
``frames.parquet`` are byte-identical. On a machine with fewer free cores than ranks, expect the
sharding overhead, not a speed-up.

Usage::

    python bench/score_bench.py                      # generates 10 sets per core concept
    python bench/score_bench.py --probes /tmp/probes --model interaction --checkpoint ckpt/interaction
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run(argv: list[str], out: Path, env: dict[str, str]) -> tuple[float, float]:
    """(scoring-loop seconds, end-to-end seconds) of one ``voe score`` launch."""
    t0 = time.perf_counter()
    res = subprocess.run([sys.executable, *argv], capture_output=True, text=True, env=env, cwd=ROOT)
    total = time.perf_counter() - t0
    if res.returncode:
        sys.exit(f"failed: {' '.join(argv)}\n{res.stderr}")
    return json.loads((out / "run.json").read_text())["wall_time_s"], total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--probes", type=Path, help="probe set (default: generate --n sets per core concept)")
    ap.add_argument("--n", type=int, default=10)
    ap.add_argument("--model", default="interaction")
    ap.add_argument("--checkpoint", type=Path)
    ap.add_argument("--batch-size", type=int, default=16)
    args = ap.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="voe-score-bench-"))
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(tmp / "xdg")}
    probes = args.probes
    if probes is None:
        from voe.concepts import CONCEPTS
        from voe.concepts.generate import generate_probe_set
        from voe.sim.scene import SimConfig

        probes = tmp / "probes"
        generate_probe_set(probes, CONCEPTS.ids(), args.n, 0, SimConfig(), jobs=2)
    from voe.io.probeset import load_probe_set

    ps = load_probe_set(probes)
    frames = len(ps) * int(ps.manifest["n_frames"])
    common = ["score", "--probes", str(probes), "--model", args.model, "--batch-size", str(args.batch_size),
              "--no-check"] + (["--checkpoint", str(args.checkpoint)] if args.checkpoint else [])
    one, two, one_t1 = tmp / "one", tmp / "two", tmp / "one-t1"
    loop1, total1 = run(["-m", "voe", *common, "--out", str(one)], one, env)
    # torchrun gives each rank OMP_NUM_THREADS=1; the same for one process separates the two effects
    loop1t, total1t = run(["-m", "voe", *common, "--out", str(one_t1)], one_t1, {**env, "OMP_NUM_THREADS": "1"})
    loop2, total2 = run(["-m", "torch.distributed.run", "--standalone", "--nproc_per_node", "2", "-m", "voe",
                         *common, "--out", str(two)], two, env)
    same = (one / "frames.parquet").read_bytes() == (two / "frames.parquet").read_bytes() \
        == (one_t1 / "frames.parquet").read_bytes()
    print(f"{args.model} on {len(ps)} clips x {ps.manifest['n_frames']} frames ({os.cpu_count()} cores)")
    print(f"{'launch':<22} {'loop frames/s':>14} {'end-to-end frames/s':>20} {'vs 1 process (loop)':>20}")
    print(f"{'1 process':<22} {frames / loop1:>14.0f} {frames / total1:>20.0f} {1.0:>20.2f}")
    print(f"{'1 process, 1 thread':<22} {frames / loop1t:>14.0f} {frames / total1t:>20.0f} {loop1 / loop1t:>20.2f}")
    print(f"{'torchrun, 2 ranks':<22} {frames / loop2:>14.0f} {frames / total2:>20.0f} {loop1 / loop2:>20.2f}")
    print(f"frames.parquet byte-identical: {same}")


if __name__ == "__main__":
    main()
