"""Trace cases of a development seed on this checkout's finder: each look's rounds (best gains
and their 5 % quantiles), what the check dropped and why, the named effects with intervals.
Usage: PYTHONPATH=<checkout> python trace.py SEED:TRUTH:NOISE [...] [--no-second-look] [--cross-fit]
Diagnosis only: nothing here changes the finder."""
import sys
import time

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder

flags = {a for a in sys.argv[1:] if a.startswith("--")}
config = GapConfig(cross_fit="--cross-fit" in flags, second_look="--no-second-look" not in flags)
for arg in (a for a in sys.argv[1:] if not a.startswith("--")):
    seed, truth, nk = arg.split(":")
    seed = int(seed)
    t0 = time.time()
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
    f = GapFinder(max_effects=3, seed=seed, config=config).fit(case.scene, case.episodes)
    print(f"== {seed} {truth} {nk}: true {case.true} ({time.time() - t0:.0f} s) scheme {f.problem_.split.scheme}")
    print(" first look:", f.first_look_)
    print(" verdict", f.verdict_, "effects", [(e["name"], e.get("params"), e.get("interval95")) for e in f.effects_])
    for i, r in enumerate(f.rounds_):
        top = sorted(r.gains.items(), key=lambda kv: -(kv[1] if np.isfinite(kv[1]) else -9))[:6]
        print(f" round {i}: before {r.before:.5f} thr {r.threshold} winner {r.winner} group {r.group}")
        print("   top gains", [(k, round(g, 4), round(r.lower.get(k, float("nan")), 4)) for k, g in top])
        for k, _ in top[:3]:
            res = r.results.get(k)
            if res is not None:
                print("   ", k, "params", np.round(getattr(res, "params", []), 4))
    for d in f.checked_.dropped:
        print(" dropped", d)
    print(" located", len(f.located_), [(round(x["t0"], 2) if "t0" in x else None, x.get("context"), round(x["z"], 1))
                                        for x in f.located_][:8])
    print(" explanation:", f.explanation_[:900])
    sys.stdout.flush()
