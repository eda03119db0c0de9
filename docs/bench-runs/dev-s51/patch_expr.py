"""How many windows a bench floor patch (out-of-library truth) is expressed in, next to the stored outcome.

A window expresses the patch when its clean prediction from the recorded start state, simulated on the
patched floor, differs from the nominal floor's by more than 3 noise sigmas RMS (``voe.gap.bench.EXPRESSED_Z``),
as the bench's ``expression`` does for library truths (which it cannot do for a patch: the patch is in the
simulated scene, not an effect). Windows: the finder's locate windows over every episode.

    python patch_expr.py ../gap_bench_s36_seed8367.jsonl ... > patch_expr.txt
"""
import json
import sys

import numpy as np

from voe.gap.bench import EXPRESSED_Z, bench_scene, make_case
from voe.gap.shooting import Shooter, choose_half, make_windows
from voe.gap.stages import GapConfig
from voe.gap.truths import hide, scene_kind

cfg = GapConfig()
for path in sys.argv[1:]:
    for ln in open(path):
        r = json.loads(ln)
        if r.get("truth") != "floor_patch":
            continue
        seed = int(r["seed"])
        rng = np.random.default_rng(seed)
        hidden = hide("floor_patch", bench_scene(scene_kind("floor_patch"), rng), rng)
        case = make_case(np.random.default_rng(seed), "floor_patch", 1e-3, 12, 3.0, noise_kind=r["noise_kind"])
        eps = case.episodes
        wins = make_windows(eps, list(range(len(eps))), cfg.locate_window)
        half = choose_half(case.scene, eps, wins, 1e-3)
        a = Shooter(case.scene, eps, 1e-3, half).simulate_many(wins, None, None)
        b = Shooter(hidden.sim_scene, eps, 1e-3, half).simulate_many(wins, None, None)
        scale = Shooter(case.scene, eps, 1e-3, half).scale
        rms = np.array([float(np.sqrt(np.mean(((x - y) * scale[None]) ** 2))) for x, y in zip(a, b, strict=True)])
        mu = hidden.sim_scene.statics[1].friction
        x0, x1 = hidden.true["friction_region"][0][1:]
        print(f"{seed} patch mu {mu:.2f} over x {x0:.2f}..{x1:.2f}: expressed in {int((rms > EXPRESSED_Z * 1e-3).sum())}"
              f"/{len(wins)} windows (max {rms.max() * 1e3:.1f} mm) | stored: {r['verdict']} {r['names']} located "
              f"{r['located']} rmse {r['before'] * 1e3:.1f} -> {r['after'] * 1e3:.1f} mm", flush=True)
