"""Speed of a full diagnosis: 20 episodes x 5 s at 100 Hz, whole effect library.

Usage: python bench/gap_speed.py [--episodes 20] [--duration 5] [--effect quadratic_drag] [--jobs 2] [--cross-fit]
Prints the answer (effects, parameters, 95 % intervals: a speed-up must not change them), the
diagnosis wall time and CPU time (this process and its workers), next to a reference measured in
the same run: stepping the same episodes once in raw pymunk at the same substep (the cost of one
nominal simulation of the data), and their ratio. Target: <= 20 s on 2 cores (``--jobs 2`` fits
candidates in two processes; ``--jobs 1`` for one core). On a shared machine the wall time
depends on the load; the CPU seconds do much less.
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
from voe.gap.stages import GapConfig
from voe.sim.scenefile import SimWorld


def children_cpu() -> float:
    """User plus system CPU seconds of this process's finished children (the candidate workers and
    the ``Ahead`` processes, each reaped when its pool shuts down: ``tests/gap/test_ahead.py``), the
    same two clocks ``time.process_time`` adds up for this process."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--episodes", type=int, default=20)
    ap.add_argument("--duration", type=float, default=5.0)
    ap.add_argument("--effect", default="quadratic_drag")
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=2, help="processes fitting candidates in parallel")
    ap.add_argument("--cross-fit", action="store_true", help="the finder cross-fits (GapConfig.cross_fit): about "
                    "twice the fitting work; the target is for the default")
    a = ap.parse_args()
    case = make_case(np.random.default_rng(a.seed), a.effect, episodes=a.episodes, duration=a.duration)
    n_samples = sum(len(e.t) for e in case.episodes)

    t0 = time.perf_counter()
    for e in case.episodes:  # reference: one raw nominal rollout of every episode
        pose0, vel0, _ = local_state(e, 0)
        SimWorld(case.scene, pose0, vel0).run(e.t, 1e-3)
    ref = time.perf_counter() - t0

    t0, c0 = time.perf_counter(), time.process_time()
    k0 = children_cpu()
    finder = GapFinder(seed=0, n_jobs=a.jobs, config=GapConfig(cross_fit=a.cross_fit)).fit(case.scene, case.episodes)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    kids = children_cpu() - k0
    found = "; ".join(f"{e['name']} " + ", ".join(f"{k} = {v:.4g} [{e['interval95'][k][0]:.4g}, {e['interval95'][k][1]:.4g}]"
                                                  for k, v in e["params"].items()) for e in finder.effects_) or "none"
    n_data, n_null = finder.problem_.shooter.n_rollouts, finder.search_.null_rollouts
    print(f"gap speed: {a.episodes} episodes x {a.duration:g} s at 100 Hz ({n_samples} samples), "
          f"episodes scheme {finder.problem_.split.scheme}, "
          f"{len(finder.problem_.candidates)} candidates, hidden {a.effect}, found {found} (verdict {finder.verdict_})")
    print(f"diagnosis wall time: {wall:.1f} s (--jobs {a.jobs}; target <= 20 s on 2 cores); cpu {cpu + kids:.1f} s "
          f"(main process {cpu:.1f} s, its workers {kids:.1f} s); os.cpu_count() = {os.cpu_count()}, "
          f"load average {os.getloadavg()[0]:.1f}")
    print(f"reference, same run: raw pymunk stepping of the same episodes (1 ms substeps) {ref:.2f} s")
    print(f"ratio to raw stepping: wall {wall / ref:.0f}x, cpu {(cpu + kids) / ref:.0f}x; simulator rollouts of 1 s "
          f"windows: {n_data} (data) + {n_null} (null), {(cpu + kids) / max(1, n_data + n_null) * 1e3:.2f} cpu-ms "
          f"per window")


if __name__ == "__main__":
    main()
