"""Probe generation throughput against raw pymunk stepping of the same scenes, measured in one run.

For each concept: generate ``--sets`` matched sets (simulate + observe + render + splice, at 64 px),
then re-build every world the generator stepped (same scene, same substeps, same number of frames,
found by a census pass that is not timed) and time pymunk alone on them: building the spaces, and
``space.step``. The ratio ``pymunk seconds / generation seconds`` is generation's throughput
relative to pymunk simulating the same scenes (1.0 would mean observing, rendering and the
concepts' logic cost nothing); it is printed against build + step and against step only. The old
reference (a generic 3-ball scene stepped for as many frames as the set stores) is printed too,
for comparison with earlier figures.

Then, unless ``--no-disk``: the whole core suite to disk with --jobs 1 and 2, and ``voe probes
export`` of it at 224 px RGB to mp4, in clips/s next to generation at 64 px.

Run: python bench/probes_bench.py [--sets 20]
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import pymunk

from voe.concepts import CONCEPTS, SUITES, get_concept
from voe.sim import world as world_mod
from voe.sim.scene import SimConfig

#: CPU seconds of this process: on a shared machine, wall time counts other people's work too.
clock = time.process_time


def census(concept, sets: int, cfg: SimConfig) -> list[tuple[tuple, int]]:
    """Every world a concept's generator builds for ``sets`` sets: (World args, frames stepped)."""
    made: list[list] = []
    orig_init, orig_step = world_mod.World.__init__, world_mod.World.step

    def init(self, scene, dt, substeps):
        orig_init(self, scene, dt, substeps)
        made.append([(scene, dt, substeps), 0])
        self._census = made[-1]

    def step(self):
        self._census[1] += 1
        orig_step(self)

    world_mod.World.__init__, world_mod.World.step = init, step
    try:
        for i in range(sets):
            concept.make_set(i, 0, cfg)
    finally:
        world_mod.World.__init__, world_mod.World.step = orig_init, orig_step
    return [(args, n) for args, n in made]


def raw_seconds(worlds: list[tuple[tuple, int]]) -> tuple[float, float]:
    """Seconds to build the census worlds' pymunk spaces, and to run only ``space.step`` on them."""
    build = step = 0.0
    for args, n in worlds:
        t0 = clock()
        w = world_mod.World(*args)
        t1 = clock()
        space, h = w.space, w.dt / w.substeps
        for _ in range(n * w.substeps):
            space.step(h)
        t2 = clock()
        build, step = build + t1 - t0, step + t2 - t1
    return build, step


def generic_seconds(n_frames: int, cfg: SimConfig) -> float:
    """The old reference: a bare space (floor + 3 balls) stepped for ``n_frames`` frames."""
    space = pymunk.Space()
    space.gravity, space.iterations = (0, -9.81), 20
    space.add(pymunk.Segment(space.static_body, (-20, 0.5), (30, 0.5), 0.1))
    for i in range(3):
        b = pymunk.Body(1, pymunk.moment_for_circle(1, 0, 0.5))
        b.position, b.velocity = (1 + 2 * i, 1.1), (2, 0)
        space.add(b, pymunk.Circle(b, 0.5))
    t0 = clock()
    for _ in range(n_frames * cfg.substeps):
        space.step(cfg.dt / cfg.substeps)
    return clock() - t0


def generation(sets: int, cfg: SimConfig) -> None:
    print(f"probe generation, {sets} sets per concept, T={cfg.n_frames}, {cfg.size}x{cfg.size}, "
          f"{cfg.substeps} substeps; reference: the same worlds, built and stepped by pymunk alone "
          f"(CPU seconds of this process)")
    print(f"{'concept':<22}{'sets/s':>8}{'frames/s':>10}{'pymunk f/s':>11}{'worlds':>7}{'build s':>8}"
          f"{'step s':>7}{'gen s':>7}{'frames/s ratio':>15}{'vs build+step':>14}{'vs step':>8}{'old ref':>8}")
    ratios, strict, old, per_frame = [], [], [], []
    for name in SUITES["core"]:
        c = get_concept(CONCEPTS.resolve(name))
        c.make_set(0, 0, cfg)  # load the spec once, outside the timing
        worlds = census(c, sets, cfg)
        t0 = clock()
        frames = sum(len(cl.rec) for i in range(sets)
                     for cl in c.make_set(i, 0, cfg).clips if cl.rec.frames is not None)  # drawn
        gen = clock() - t0
        build, step = raw_seconds(worlds)
        ratios.append((build + step) / gen)
        strict.append(step / gen)
        old.append(generic_seconds(frames, cfg) / gen)
        stepped = sum(n for _, n in worlds) / step  # frames per second pymunk steps these worlds
        per_frame.append(frames / gen / stepped)
        print(f"{c.id:<22}{sets / gen:>8.1f}{frames / gen:>10.0f}{stepped:>11.0f}{len(worlds):>7}"
              f"{build:>8.3f}{step:>7.3f}{gen:>7.3f}{per_frame[-1]:>14.2f}x{ratios[-1]:>13.2f}x"
              f"{strict[-1]:>7.2f}x{old[-1]:>7.2f}x")
    print(f"median throughput, stored frames/s over the frames/s pymunk steps the same worlds: "
          f"{statistics.median(per_frame):.2f}x (target >= 0.5x; a spliced clip's frames are not "
          f"stepped again)")
    print(f"median for the same work (every world the generator steps, pymunk alone): "
          f"{statistics.median(ratios):.2f}x building and stepping, {statistics.median(strict):.2f}x "
          f"stepping only; old reference (a generic 3-ball scene stepped for the stored frames): "
          f"{statistics.median(old):.2f}x")


def cpu_all() -> float:
    """CPU seconds of this process and of its finished children (pool workers, ffmpeg)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def disk(sets: int, cfg: SimConfig) -> None:
    from voe.concepts.generate import generate_probe_set
    from voe.io.export import export_probe_set

    ids = [CONCEPTS.resolve(n) for n in SUITES["core"]]
    print(f"to disk (load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; clips per wall "
          f"second, and per CPU second of all processes)")

    def line(what: str, run) -> int:
        w0, c0 = time.perf_counter(), cpu_all()
        n = run()
        wall, cpu = time.perf_counter() - w0, cpu_all() - c0
        print(f"  {what:<40}{n:>5} clips {wall:>7.1f} s wall {n / wall:>7.1f} clips/s "
              f"{n / cpu:>7.1f} clips/CPU-s")
        return n

    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        for jobs in (1, 2):
            line(f"generate core suite, {cfg.size} px gray, --jobs {jobs}",
                 lambda j=jobs: generate_probe_set(root / f"p{j}", ids, sets, 0, cfg, jobs=j)["n_clips"])
        for fmt, jobs in (("mp4", 1), ("mp4", 2), ("png", 1)):
            line(f"export 224 px RGB {fmt}, --jobs {jobs}",
                 lambda f=fmt, j=jobs: export_probe_set(root / "p1", root / f"x-{f}{j}", fmt=f, size=224,
                                                        rgb=True, jobs=j)["n_clips"])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sets", type=int, default=20)
    ap.add_argument("--no-disk", action="store_true", help="skip generation to disk and export")
    args = ap.parse_args()
    cfg = SimConfig()
    generation(args.sets, cfg)
    if not args.no_disk:
        disk(args.sets, cfg)


if __name__ == "__main__":
    main()
