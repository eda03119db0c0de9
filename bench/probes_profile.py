"""Where probe generation spends its time: CPU seconds per stage, core suite.

Wraps the stages of generation with CPU-time counters (nested stages are counted in each: the
frames of a quadruplet's possible clips are drawn inside ``splice``) and generates ``--sets``
matched sets of every core concept in this process.

Run: python bench/probes_profile.py [--sets 10]
"""

from __future__ import annotations

import argparse
import collections
import time

from voe.concepts import CONCEPTS, SUITES, get_concept
from voe.concepts import base as concept_base
from voe.sim import render, rollout, world
from voe.sim.scene import SimConfig

STAGES = (  # (object, attribute, label)
    (world.World, "__init__", "build pymunk worlds"),
    (world.World, "step", "pymunk stepping (World.step)"),
    (rollout.Recorder, "capture", "read poses (per frame)"),
    (rollout.Recorder, "result", "decode poses + visibility"),
    (render.Renderer, "__init__", "renderer set-up (backgrounds)"),
    (render.Renderer, "clip", "draw clips"),
    (concept_base, "splice", "splice (draws A and B first)"),
)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sets", type=int, default=10)
    args = ap.parse_args()
    spent: collections.Counter[str] = collections.Counter()
    for obj, name, label in STAGES:
        fn = getattr(obj, name)

        def timed(*a, _fn=fn, _label=label, **kw):
            t0 = time.process_time()
            try:
                return _fn(*a, **kw)
            finally:
                spent[_label] += time.process_time() - t0

        setattr(obj, name, timed)
    cfg = SimConfig()
    concepts = [get_concept(CONCEPTS.resolve(n)) for n in SUITES["core"]]
    for c in concepts:
        c.make_set(0, 0, cfg)  # specs loaded outside the measurement
    spent.clear()
    t0 = time.process_time()
    for c in concepts:
        for i in range(args.sets):
            c.make_set(i, 0, cfg)
    total = time.process_time() - t0
    print(f"core suite, {args.sets} sets per concept, CPU seconds (nested stages counted in each)")
    for label, sec in spent.most_common():
        print(f"  {label:<34}{sec:7.3f} s {100 * sec / total:5.1f} %")
    print(f"  {'total':<34}{total:7.3f} s")


if __name__ == "__main__":
    main()
