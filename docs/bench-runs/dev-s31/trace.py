"""Trace stored untouched cases (seed 2307, --cross-fit; bench defaults noise 1e-3, 12 episodes x 3 s):
rerun each case on main's finder and print its rounds, what the check dropped and why, and the
explanation. Diagnosis only: nothing here changes the finder."""
import json, sys, time
import numpy as np
from voe.gap.bench import make_case, expression
from voe.gap.finder import GapConfig, GapFinder

for arg in sys.argv[1:]:
    seed, truth, nk = arg.split(":")
    seed = int(seed)
    t0 = time.time()
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
    f = GapFinder(max_effects=3, seed=seed, config=GapConfig(cross_fit=True)).fit(case.scene, case.episodes)
    print(f"== {seed} {truth} {nk}: true {case.true}  ({time.time() - t0:.0f} s)")
    print("verdict", f.verdict_, "effects", [(e['name'], e.get('params')) for e in f.effects_])
    for i, r in enumerate(f.rounds_):
        top = sorted(r.gains.items(), key=lambda kv: -(kv[1] if np.isfinite(kv[1]) else -9))[:5]
        print(f" round {i}: before {r.before:.5f} thr {r.threshold} winner {r.winner} basis {r.basis}")
        print("   top gains", [(k, round(g, 4), round(r.lower.get(k, float('nan')), 4)) for k, g in top])
        for k, _ in top[:2]:
            res = r.results.get(k)
            if res is not None:
                print("   ", k, "params", np.round(getattr(res, 'params', []), 4))
    for d in f.checked_.dropped:
        print(" dropped", d)
    print(" located", len(f.located_), "explanation:", f.explanation_[:600])
    sys.stdout.flush()
