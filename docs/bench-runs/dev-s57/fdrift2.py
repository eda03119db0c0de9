"""Dev harness (session 56, rebuilt in session 57): the flight drift test's before/after contrasts
with three, two or one unit(s) a side. A copy of dev-s55/fdrift.py cut to the landed test ("hyb":
Welch on one slot against the rest, pooled on before/after splits) with the side a parameter.

Gusts: each library effect that pushes in flight, flight-fitted from its first six starts (lowest
soft-L1 cost); caught = the test finds time variation. Singles/compounds: the truth at its true
parameters; caught = a false drop.

usage: python fdrift2.py gust|single|compound SEED_BASE ...
"""
import json
import sys

import numpy as np
from scipy.stats import t as student

from voe.gap import drift_flight as D
from voe.gap.bench import make_case, plan
from voe.gap.drift_base import ALPHA, MATERIAL
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.prefit import flight_samples, seen_missing
from voe.gap.stages import context_for

VARIANTS = {"hyb": (3, 1), "hyb_s2": (2, 1), "hyb_s1": (1, 1), "hyb_s2f2": (2, 2)}
# (units a before/after side needs, a slot always 3; the material floor's multiple for a side under three units)
PUSHERS = ("spring_anchor", "point_attractor", "linear_drag", "quadratic_drag", "constant_acceleration")


def crit(df, n):
    return float(student.ppf(1 - ALPHA / (2 * max(n, 1)), max(df, 1)))


def unit_table(seen, e, p, scene, ctx):
    """(U, 2) unit residuals, (U,) slots and the material floor, as ``flight_drift`` builds them."""
    params = D._flight_fit(seen, e, p, scene, ctx)
    res = seen.dacc - seen_missing(e, params, seen, scene)[0]
    slot = np.floor(seen.time / D.FLIGHT_SLOT).astype(int)
    units, labels = [], []
    for key in sorted(set(zip(seen.episode.tolist(), slot.tolist(), strict=True))):
        m = (seen.episode == key[0]) & (slot == key[1])
        if m.sum() >= D.MIN_UNIT:
            units.append(np.median(res[m], axis=0))
            labels.append(key[1])
    if len(units) < 6:
        return None
    u = np.array(units)
    mad = 1.4826 * np.median(np.abs(u - np.median(u, axis=0)), axis=0)
    keep = np.all(np.abs(u - np.median(u, axis=0)) <= D.OUTLIER * np.maximum(mad, 1e-9), axis=1)
    u, lab = u[keep], np.array(labels)[keep]
    if len(u) < 6:
        return None
    return u, lab, MATERIAL * float(np.median(np.linalg.norm(seen.dacc, axis=1)))


def contrasts(lab, side):
    """(name, mask): each slot against the rest (three units a side), before/after each boundary
    (``side`` units a side), no split twice."""
    cands = [(f"slot {a}", lab == a, 3) for a in np.unique(lab)]
    cands += [(f"cp {a}", lab < a, side) for a in np.unique(lab)[1:]]
    out = []
    for n, m, k in cands:
        if k <= m.sum() <= len(lab) - k and not any(np.array_equal(m, q) or np.array_equal(m, ~q) for _, q in out):
            out.append((n, m))
    return out


def t_stat(x, y, pooled):
    if pooled:
        df = len(x) + len(y) - 2
        sp = np.sqrt((((x - x.mean()) ** 2).sum() + ((y - y.mean()) ** 2).sum()) / df)  # a side of one unit adds 0
        return abs(x.mean() - y.mean()) / max(sp * np.sqrt(1 / len(x) + 1 / len(y)), 1e-12), df
    vx, vy = x.var(ddof=1) / len(x), y.var(ddof=1) / len(y)
    if vx + vy <= 0:
        return 0.0, 1
    df = (vx + vy) ** 2 / (vx**2 / (len(x) - 1) + vy**2 / (len(y) - 1))
    return abs(x.mean() - y.mean()) / np.sqrt(vx + vy), int(np.floor(df))


def test(tab, variant):
    """The worst material, significant contrast (name, t), or None."""
    side, mult = variant
    if tab is None:
        return None
    u, lab, floor = tab
    cs = contrasts(lab, side)
    worst = None
    for name, m in cs:
        for j in range(2):
            x, y = u[m, j], u[~m, j]
            z, df = t_stat(x, y, name.startswith("cp"))
            need = floor * (mult if min(m.sum(), (~m).sum()) < 3 else 1)
            if abs(x.mean() - y.mean()) >= need and z > crit(df, 2 * len(cs)) and (worst is None or z > worst[1]):
                worst = (name + " " + "xy"[j], round(float(z), 1))
    return worst


def best_flight_fit(seen, e, ctx, scene):
    best = None
    for st in e.starts(ctx)[:6]:
        pp = D._flight_fit(seen, e, np.asarray(st, float), scene, ctx)
        r = seen.dacc - seen_missing(e, pp, seen, scene)[0]
        c = float(np.sum(np.sqrt(1 + (r / 0.1) ** 2) - 1))
        if best is None or c < best[0]:
            best = (c, pp)
    return best[1]


def run(seed_base, which):
    for s, truth, _nk, role in plan(130, seed_base, compound=8, outside=12, clean=0):
        if which == "gust" and truth != "gust":
            continue
        if which == "single" and (role != "cycle" or truth == "none"):
            continue
        if which == "compound" and role != "compound":
            continue
        case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind="white")
        if case.scene.joints:
            continue
        eps = case.episodes[:6]
        seen = flight_samples(case.scene, eps, around=True)
        if seen is None or seen.time is None or len(seen) < 30:
            print(json.dumps({"seed": s, "truth": truth, "none": True}), flush=True)
            continue
        ctx = context_for(case.scene, eps)
        rec = {"seed": s, "truth": truth}
        if truth == "gust":
            for name in PUSHERS:
                e = EFFECTS.get(name)()
                tab = unit_table(seen, e, best_flight_fit(seen, e, ctx, case.scene), case.scene, ctx)
                rec[name] = {v: test(tab, k) for v, k in VARIANTS.items()}
        else:
            parts = [EFFECTS.get(n)(bodies=b) for n, (p, b) in case.true.items()]
            e = parts[0] if len(parts) == 1 else EffectSum(tuple(parts))
            p = np.concatenate([p for n, (p, b) in case.true.items()])
            if not D.flight_movers(ctx.flight, e, p, case.scene, ctx):
                continue
            rec["truth_eff"] = {v: test(unit_table(seen, e, p, case.scene, ctx), k) for v, k in VARIANTS.items()}
        print(json.dumps(rec), flush=True)


if __name__ == "__main__":
    for sb in map(int, sys.argv[2:]):
        run(sb, sys.argv[1])
