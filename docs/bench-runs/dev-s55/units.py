"""Flight units (episode, slot) of a case's fitting episodes after each library effect's flight fit."""
import sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap import drift as D
from voe.gap.prefit import flight_samples, seen_missing
from voe.gap.effects import EFFECTS
from voe.gap.stages import context_for

def setup(seed, truth):
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind="white")
    eps = case.episodes[:6]
    seen = flight_samples(case.scene, eps, around=True)
    ctx = context_for(case.scene, eps)
    return case, seen, ctx

def best_fit(seen, e, ctx, scene):
    best = None
    for s in e.starts(ctx)[:6]:
        p = D._flight_fit(seen, e, np.asarray(s, float), scene, ctx)
        acc, _ = seen_missing(e, p, seen, scene)
        r = seen.dacc - acc
        cost = float(np.sum(np.sqrt(1 + (r / 0.1) ** 2) - 1))
        if best is None or cost < best[0]:
            best = (cost, p)
    return best[1]

def units(seen, e, p, scene):
    acc, _ = seen_missing(e, p, seen, scene)
    res = seen.dacc - acc
    slot = np.floor(seen.time / D.FLIGHT_SLOT).astype(int)
    out = []
    for key in sorted(set(zip(seen.episode.tolist(), slot.tolist()))):
        m = (seen.episode == key[0]) & (slot == key[1])
        if m.sum() >= D.MIN_UNIT:
            out.append((key[0], key[1], np.median(res[m], axis=0), int(m.sum())))
    return out

if __name__ == "__main__":
    np.set_printoptions(precision=3, suppress=True)
    truth = sys.argv[1]
    for seed in map(int, sys.argv[2:]):
        case, seen, ctx = setup(seed, truth)
        print(seed, "flight n", None if seen is None else len(seen), "median |dacc|", np.median(np.linalg.norm(seen.dacc, axis=1)))
        for name in ("spring_anchor",):
            e = EFFECTS.get(name)()
            p = best_fit(seen, e, ctx, case.scene)
            print(" ", name, p, D.flight_drift(seen, e, p, case.scene, ctx))
            for u in units(seen, e, p, case.scene):
                print("    ep", u[0], "slot", u[1], u[2], u[3])
