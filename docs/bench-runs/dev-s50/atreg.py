"""Selection gains of a region winner, its global form as fitted, and its global form at the
region's own strength (the region's parameters without the interval), each round (diagnosis only).

    python atreg.py SEED:TRUTH:NOISE [max_effects]
"""
import sys

import numpy as np

import voe.gap.greedy as gm
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder
from voe.gap.search import window_gain

seed, truth, nk = sys.argv[1].split(":")
orig = gm.refined_race


def race(fitter, results, gains, thr, before_sse, n_jobs):
    out = orig(fitter, results, gains, thr, before_sse, n_jobs)
    res, g = out[0], out[1]
    for k, r in res.items():
        part = r.effect.parts[-1]
        plain = part.global_name
        if plain is None or plain not in res:
            continue
        fp = tuple(np.asarray(p)[:-2] for p in r.fold_params)  # the interval dropped
        sse = fitter.heldout_sse(res[plain].effect, fp)
        ga = window_gain(before_sse, sse)
        print(f"ROUND thr={thr if thr is None else round(100 * thr, 1)} {k}: gain {100 * g[k]:.1f} % params "
              f"{[np.round(p, 4).tolist() for p in r.fold_params]}; {plain}: gain {100 * g[plain]:.1f} % params "
              f"{[np.round(p, 4).tolist() for p in res[plain].fold_params]}; {plain} at {k}'s strength: gain "
              f"{100 * ga:.1f} %", flush=True)
    return out


gm.refined_race = race
case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
me = int(sys.argv[2]) if len(sys.argv) > 2 else 3
f = GapFinder(max_effects=me, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
print("VERDICT", f.verdict_, [e["name"] for e in f.effects_], flush=True)
