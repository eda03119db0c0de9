"""How often does the search's fit of the TRUE effect land in a worse valley than a fit started at the truth?
Dev cases only (stores of development seeds). Fold-level, as the search fits a candidate in round 1:
fit_candidate (own starts) then refine, the better by selection gain kept; the oracle: the same from the true
parameters. Usage: PYTHONPATH=<checkout> python valleys.py STORE.jsonl [--variant NAME] [--limit N] [--jobs J]"""
import argparse, json, sys, time
import numpy as np
from voe.gap.bench import make_case
from voe.gap.search import window_gain
from voe.gap.stages import GapConfig, _folded, prepare
from voe.parallel import parallel_map
import variants

def one(args):
    cid, truth, nk, variant = args
    variants.apply(variant)
    t0 = time.process_time()
    case = make_case(np.random.default_rng(cid), truth, 1e-3, 12, 3.0, noise_kind=nk)
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, (truth,), cfg)
    key = truth if truth in p.candidates else f"{truth}[{case.bodies[0]}]"
    if key not in p.candidates:
        return None
    data = _folded(p, p.shooter, p.episodes, p.bad, cfg, cid)
    before = data.heldout_sse(None, None)
    def search_like(res):
        ref = data.refine(res)
        return ref if window_gain(before, ref.window_sse) >= window_gain(before, res.window_sse) else res
    raw = data.fit_candidate(None, p.candidates[key])
    t_fit = time.process_time() - t0
    res = search_like(raw)
    true = np.where(np.isnan(case.params), res.params, case.params)
    lo, hi = res.effect.bounds(data.folds[0].ctx)
    true = np.clip(true, lo, hi)
    orc = data.refit(res.effect, tuple(true for _ in data.folds))
    cost_true = sum(f.cost(res.effect, true) for f in data.folds)
    return {"id": cid, "truth": truth, "nk": nk, "params": res.params.tolist(), "true": case.params.tolist(),
            "cost": raw.train_cost, "gain": window_gain(before, raw.window_sse), "raw_params": raw.params.tolist(),
            "r_cost": res.train_cost, "r_gain": window_gain(before, res.window_sse),
            "o_params": orc.params.tolist(), "o_cost": orc.train_cost, "o_gain": window_gain(before, orc.window_sse),
            "cost_at_true": cost_true, "cpu_fit": t_fit}

ap = argparse.ArgumentParser()
ap.add_argument("store"); ap.add_argument("--variant", default="main"); ap.add_argument("--limit", type=int, default=0)
ap.add_argument("--jobs", type=int, default=1); ap.add_argument("--truths", default=""); ap.add_argument("--out", required=True)
a = ap.parse_args()
recs = [json.loads(l) for l in open(a.store).read().splitlines()[1:]]
todo = [(r["seed"], r["truth"], r["noise_kind"], a.variant) for r in recs
        if r["kind"] == "single" and r["truth"] != "none" and r.get("role") in (None, "cycle")]
if a.truths:
    todo = [t for t in todo if t[1] in a.truths.split(",")]
if a.limit:
    todo = todo[:a.limit]
t0 = time.time()
with open(a.out, "w") as fh:
    for r in parallel_map(one, todo, a.jobs):
        if r is None:
            continue
        fh.write(json.dumps(r) + "\n"); fh.flush()
        worse = (r["cost"] - r["o_cost"]) / max(r["o_cost"], 1e-9)
        print(f"{r['id']} {r['truth']:24s} cost {r['cost']:10.1f} oracle {r['o_cost']:10.1f} ({100*worse:+6.1f} %) "
              f"gain {r['gain']:.3f} refined {r['r_gain']:.3f} oracle {r['o_gain']:.3f}  cpu {r['cpu_fit']:.1f}s", flush=True)
print("wall", time.time() - t0)
