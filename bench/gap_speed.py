"""Speed of a full diagnosis: 20 episodes x 5 s at 100 Hz, whole effect library.

Usage: python bench/gap_speed.py [--episodes 20] [--duration 5] [--effect quadratic_drag]
Prints the diagnosis wall time next to a reference: stepping the same episodes once in raw
pymunk at the same substep (the cost of one nominal simulation of the data), and their ratio.
Target: <= 20 s on 2 cores (``--jobs 2`` fits candidates in two processes; ``--jobs 1`` for one core).
"""

from __future__ import annotations

import argparse
import os
import resource
import time

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.shooting import local_state
from voe.sim.scenefile import SimWorld


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--episodes", type=int, default=20)
    ap.add_argument("--duration", type=float, default=5.0)
    ap.add_argument("--effect", default="quadratic_drag")
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=2, help="processes fitting candidates in parallel")
    a = ap.parse_args()
    case = make_case(np.random.default_rng(a.seed), a.effect, episodes=a.episodes, duration=a.duration)
    n_samples = sum(len(e.t) for e in case.episodes)

    t0 = time.perf_counter()
    for e in case.episodes:  # reference: one raw nominal rollout of every episode
        pose0, vel0, _ = local_state(e, 0)
        SimWorld(case.scene, pose0, vel0).run(e.t, 1e-3)
    ref = time.perf_counter() - t0

    t0, c0 = time.perf_counter(), time.process_time()
    k0 = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    finder = GapFinder(seed=0, n_jobs=a.jobs).fit(case.scene, case.episodes)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - k0
    found = [e["name"] for e in finder.effects_] or ["none"]
    print(f"gap speed: {a.episodes} episodes x {a.duration:g} s at 100 Hz ({n_samples} samples), "
          f"{len(finder.problem_.candidates)} candidates, hidden {a.effect}, found {', '.join(found)}")
    print(f"diagnosis wall time: {wall:.1f} s (--jobs {a.jobs}, cpu of the main process {cpu:.1f} s, of its workers "
          f"{kids:.1f} s; target <= 20 s on 2 cores; "
          f"os.cpu_count() = {os.cpu_count()}, load average {os.getloadavg()[0]:.1f})")
    print(f"reference raw pymunk stepping of the same episodes (1 ms substeps): {ref:.2f} s")
    print(f"ratio diagnosis / raw stepping: {wall / ref:.0f}x; simulator rollouts of windows: "
          f"{finder.problem_.shooter.n_rollouts} (data), i.e. {wall / max(1, finder.problem_.shooter.n_rollouts) * 1e3:.1f} ms per window")


if __name__ == "__main__":
    main()
