"""Print every round's full gains/lower/threshold and the group/tie info for given cases (diagnosis only)."""
import sys, time
import numpy as np
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder
for arg in sys.argv[1:]:
    seed, truth, nk = arg.split(":"); seed = int(seed)
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
    f = GapFinder(max_effects=3, seed=seed, config=GapConfig()).fit(case.scene, case.episodes)
    print("==", seed, truth, case.true, f.verdict_, [e["name"] for e in f.effects_])
    for i, r in enumerate(f.rounds_):
        print(f" round {i}: thr {r.threshold} winner {r.winner} group {r.group}")
        for k, g in sorted(r.gains.items(), key=lambda kv: -(kv[1] if np.isfinite(kv[1]) else -9)):
            print(f"    {k:28s} {g: .4f} {r.lower.get(k, float('nan')): .4f}")
        print("   ", {a: getattr(r, a) for a in vars(r) if a not in ("gains", "lower", "results")})
