"""Probe generation throughput, measured next to raw pymunk stepping of the same scenes.

Prints, per concept: matched sets/s and frames/s of full generation (simulate + observe + render +
splice), the time raw pymunk takes to step the same number of frames (same substeps), and the
ratio. Also the wall time of a whole core-suite generation to disk with --jobs 1 and 2.

Run: python bench/probes_bench.py [--sets 20]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import pymunk

from voe.concepts import CONCEPTS, SUITES, get_concept
from voe.concepts.generate import generate_probe_set
from voe.sim.scene import SimConfig


def raw_pymunk_seconds(n_frames: int, substeps: int, dt: float, n_bodies: int) -> float:
    """Step a bare pymunk space (floor + n bodies) for n_frames frames."""
    space = pymunk.Space()
    space.gravity = (0, -9.81)
    space.iterations = 20
    floor = pymunk.Segment(space.static_body, (-20, 0.5), (30, 0.5), 0.1)
    space.add(floor)
    for i in range(n_bodies):
        b = pymunk.Body(1, pymunk.moment_for_circle(1, 0, 0.5))
        b.position = (1 + 2 * i, 1.1)
        b.velocity = (2, 0)
        space.add(b, pymunk.Circle(b, 0.5))
    t0 = time.perf_counter()
    for _ in range(n_frames * substeps):
        space.step(dt / substeps)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sets", type=int, default=20)
    args = ap.parse_args()
    cfg = SimConfig()
    print(f"probe generation, {args.sets} sets per concept, T={cfg.n_frames}, {cfg.size}x{cfg.size}, "
          f"{cfg.substeps} substeps")
    print(f"{'concept':<22}{'sets/s':>9}{'frames/s':>11}{'raw pymunk frames/s':>21}{'ratio':>8}")
    ratios = []
    for name in SUITES["core"]:
        cid = CONCEPTS.resolve(name)
        c = get_concept(cid)
        t0 = time.perf_counter()
        frames = 0
        for i in range(args.sets):
            m = c.make_set(i, 0, cfg)
            frames += sum(len(cl.rec) for cl in m.clips)
        gen = time.perf_counter() - t0
        raw = raw_pymunk_seconds(frames, cfg.substeps, cfg.dt, 3)
        ratio = gen / raw
        ratios.append(ratio)
        print(f"{cid:<22}{args.sets / gen:>9.1f}{frames / gen:>11.0f}{frames / raw:>21.0f}{ratio:>8.2f}")
    print(f"median cost relative to raw pymunk stepping: {statistics.median(ratios):.2f}x")
    for jobs in (1, 2):
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            m = generate_probe_set(Path(tmp) / "p", [CONCEPTS.resolve(n) for n in SUITES["core"]],
                                   args.sets, 0, cfg, jobs=jobs)
            wall = time.perf_counter() - t0
        print(f"core suite to disk, --per-concept {args.sets} --jobs {jobs}: {m['n_clips']} clips in "
              f"{wall:.1f} s ({m['n_clips'] * cfg.n_frames / wall:.0f} frames/s)")


if __name__ == "__main__":
    main()
