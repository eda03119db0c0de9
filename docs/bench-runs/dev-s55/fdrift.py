"""Dev harness: flight time-variation tests, current vs change-point variants.

Gusts: each library effect that moves bodies in flight, flight-fitted from its starts (best cost);
flagged = the test finds time variation. Singles/compounds: the truth at its true parameters;
flagged = a false drop.
"""
import sys, json
import numpy as np
from scipy.stats import t as student
from voe.gap.bench import make_case, plan
from voe.gap import drift as D
from voe.gap.prefit import flight_samples, seen_missing
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.stages import context_for

def crit(df, n):
    return float(student.ppf(1 - D.ALPHA / (2 * max(n, 1)), max(df, 1)))

def unit_table(seen, e, p, scene):
    params = D._flight_fit(seen, e, p, scene, CTX[0])
    acc, _ = seen_missing(e, params, seen, scene)
    res = seen.dacc - acc
    slot = np.floor(seen.time / D.FLIGHT_SLOT).astype(int)
    units, labels = [], []
    for key in sorted(set(zip(seen.episode.tolist(), slot.tolist()))):
        m = (seen.episode == key[0]) & (slot == key[1])
        if m.sum() >= D.MIN_UNIT:
            units.append(np.median(res[m], axis=0)); labels.append(key[1])
    if len(units) < 6:
        return None
    u = np.array(units)
    mad = 1.4826 * np.median(np.abs(u - np.median(u, axis=0)), axis=0)
    keep = np.all(np.abs(u - np.median(u, axis=0)) <= D.OUTLIER * np.maximum(mad, 1e-9), axis=1)
    u, lab = u[keep], np.array(labels)[keep]
    if len(u) < 6:
        return None
    floor = D.MATERIAL * float(np.median(np.linalg.norm(seen.dacc, axis=1)))
    return u, lab, floor

def welch(x, y):
    vx, vy = x.var(ddof=1) / len(x), y.var(ddof=1) / len(y)
    se = np.sqrt(vx + vy)
    if se <= 0: return 0.0, 1
    df = (vx + vy) ** 2 / (vx**2 / (len(x) - 1) + vy**2 / (len(y) - 1))
    return abs(x.mean() - y.mean()) / se, int(np.floor(df))

def pooled(x, y):
    sp = np.sqrt(((len(x) - 1) * x.var(ddof=1) + (len(y) - 1) * y.var(ddof=1)) / (len(x) + len(y) - 2))
    return abs(x.mean() - y.mean()) / max(sp * np.sqrt(1 / len(x) + 1 / len(y)), 1e-12), len(x) + len(y) - 2

def best_flight_fit(seen, e, ctx, scene):
    """``e``'s parameters fitted in flight from each of its first six starts, the lowest soft-L1 cost kept."""
    best = None
    for st in e.starts(ctx)[:6]:
        pp = D._flight_fit(seen, e, np.asarray(st, float), scene, ctx)
        r = seen.dacc - seen_missing(e, pp, seen, scene)[0]
        c = float(np.sum(np.sqrt(1 + (r / 0.1) ** 2) - 1))
        if best is None or c < best[0]: best = (c, pp)
    return best[1]

def contrasts(lab, kind):
    """(name, mask) splits of units."""
    out = []
    if kind in ("slot", "both"):
        out += [(f"slot {a}", lab == a) for a in np.unique(lab)]
    if kind in ("cp", "both"):
        out += [(f"cp {a}", lab < a) for a in np.unique(lab)[1:]]
    ded = []
    for n, m in out:
        if 3 <= m.sum() <= len(lab) - 3 and not any(np.array_equal(m, mm) or np.array_equal(m, ~mm) for _, mm in ded):
            ded.append((n, m))
    return ded

def test(tab, kind, how="welch"):
    if tab is None: return None
    if how == "union":
        a = test(tab, kind, "welch2") 
        return a if a is not None else test(tab, kind, "pooled2")
    u, lab, floor = tab
    cs = contrasts(lab, kind)
    n = 2 * len(cs) * (2 if how.endswith("2") else 1)
    how = how.rstrip("2")
    worst = None
    for name, m in cs:
        for j in range(2):
            x, y = u[m, j], u[~m, j]
            # hyb (landed): Welch on single slots, pooled on before/after splits
            stat = how if how != "hyb" else ("welch" if name.startswith("slot") else "pooled")
            z, df = welch(x, y) if stat == "welch" else pooled(x, y)
            if abs(x.mean() - y.mean()) >= floor and z > crit(df, n) and (worst is None or z > worst[1]):
                worst = (name + " " + "xy"[j], round(float(z), 1))
    return worst

VARIANTS = {"cur": ("slot", "welch"), "cp": ("cp", "welch"), "both": ("both", "welch"), "both_pooled": ("both", "pooled"),
            "slot_pooled": ("slot", "pooled"), "cp_pooled": ("cp", "pooled"),
            "both_union": ("both", "union"), "slot_union": ("slot", "union"), "hyb": ("both", "hyb")}
CTX = [None]

def run(seed_base, which):
    rows = plan(130, seed_base, compound=8, outside=12, clean=0)
    out = []
    for s, truth, nk, role in rows:
        if which == "gust" and truth != "gust": continue
        if which == "single" and (role != "cycle" or truth == "none"): continue
        if which == "compound" and role != "compound": continue
        case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind="white")
        if case.scene.joints: continue
        eps = case.episodes[:6]
        seen = flight_samples(case.scene, eps, around=True)
        if seen is None or seen.time is None or len(seen) < 30:
            out.append({"seed": s, "truth": truth, "none": True}); continue
        CTX[0] = ctx = context_for(case.scene, eps)
        rec = {"seed": s, "truth": truth}
        if truth == "gust":
            for name in ("spring_anchor", "point_attractor", "linear_drag", "quadratic_drag", "constant_acceleration"):
                e = EFFECTS.get(name)()
                tab = unit_table(seen, e, best_flight_fit(seen, e, ctx, case.scene), case.scene)
                rec[name] = {v: test(tab, *VARIANTS[v]) for v in VARIANTS}
        else:
            parts = [EFFECTS.get(n)(bodies=b) for n, (p, b) in case.true.items()]
            e = parts[0] if len(parts) == 1 else EffectSum(tuple(parts))
            p = np.concatenate([p for n, (p, b) in case.true.items()])
            if not D.flight_movers(ctx.flight, e, p, case.scene, ctx):
                continue
            tab = unit_table(seen, e, p, case.scene)
            rec["truth_eff"] = {v: test(tab, *VARIANTS[v]) for v in VARIANTS}
        out.append(rec)
        print(json.dumps(rec), flush=True)
    return out

if __name__ == "__main__":
    which = sys.argv[1]
    for sb in map(int, sys.argv[2:]):
        run(sb, which)
