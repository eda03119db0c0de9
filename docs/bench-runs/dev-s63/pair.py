"""A paired development bench: the bench's own cases (``voe.gap.bench.run_case``) of a finished run's store,
rerun on the current code, each record written beside the stored one (development only).

    PYTHONPATH=<clone> python pair.py run STORE.jsonl OUT.jsonl [--order random|plan] [--seed N] [--part I/N]
    PYTHONPATH=<clone> python pair.py score STORE.jsonl OUT.jsonl [OUT2.jsonl ...]

``run`` resumes: cases already in OUT or in any pair_*.jsonl beside it are skipped; ``--seeds a,b,c`` runs those
cases only, in that order. ``--order random`` shuffles the plan with ``--seed`` so that
a run stopped early is a random sample of it; ``--part I/N`` takes every N-th case of that order from the I-th
(one process per core). ``score`` prints the bench's summary lines for the stored and the new records of the
cases done, then every case whose verdict, names or rightness changed.
"""
import glob
import json
import os
import sys
import time

import numpy as np

from voe.gap.bench_score import false_discovery, misnamed, outside_right, summary_lines


def stored(path):
    recs = {}
    with open(path) as f:
        for ln in f:
            try:
                d = json.loads(ln)
            except json.JSONDecodeError:
                continue
            if "truth" in d:
                recs[d["seed"]] = d
    return recs


def right(r):
    """As the bench scores the case's role: a cycle case names its truth first (none: names nothing), a
    compound names both, an out-of-library case is not misnamed and is named right or unexplained and
    located, an extra clean case is not a false discovery."""
    if r["kind"] == "outside":
        return outside_right(r) and not misnamed(r)
    if r["kind"] == "compound":
        return set(r["truth"].split("+")) <= set(r["names"])
    if r.get("role") == "cycle":
        return r["found"] == r["truth"]
    return not false_discovery(r)


def run(store, out, order="random", seed=0, part="0/1", only=None):
    from voe.gap.bench import run_case
    old = stored(store)
    seeds = sorted(old)
    if order == "random":
        seeds = list(np.random.default_rng(seed).permutation(seeds))
    i, n = map(int, part.split("/"))
    seeds = [int(s) for s in (only or seeds)][i::n]
    siblings = glob.glob(os.path.join(os.path.dirname(os.path.abspath(out)), "pair_*.jsonl"))
    with open(out, "a") as f:
        for s in seeds:
            if any(s in stored(p) for p in siblings + [out] if os.path.exists(p)):  # done here or by another part
                continue
            o = old[int(s)]
            t0 = time.time()
            r = run_case((int(s), o["truth"], 1e-3, 3, 12, 3.0, o["noise_kind"]))
            r["elapsed"] = round(time.time() - t0, 1)
            r["role"] = o.get("role")
            r["stored"] = o
            f.write(json.dumps(r) + "\n")
            f.flush()
            print(f"{s} {o['truth']} {o['noise_kind']}: stored {o['names']} {o['verdict']} -> now {r['names']} "
                  f"{r['verdict']} ({r['elapsed']} s)", file=sys.stderr, flush=True)


def score(store, outs):
    new = {}
    for o in outs:
        new.update(stored(o))
    olds = [new[s]["stored"] for s in sorted(new)]
    news = [{k: v for k, v in new[s].items() if k != "stored"} for s in sorted(new)]
    print(f"{len(news)} cases rerun")
    for label, rs in (("stored", olds), ("now", news)):
        print(f"--- {label}")
        for ln in summary_lines(rs, 1e-3):
            print(ln)
    print("--- changed (seed truth noise: stored -> now)")
    for o, r in zip(olds, news):
        if (o["names"], o["verdict"]) != (r["names"], r["verdict"]):
            flip = {(True, False): "RIGHT->WRONG", (False, True): "wrong->right"}.get((right(o), right(r)), "")
            print(f"{o['seed']} {o['truth']} {o['noise_kind']}: {o['names']} {o['verdict']} -> {r['names']} "
                  f"{r['verdict']} {flip}")
    k_old, k_new = sum(map(right, olds)), sum(map(right, news))
    print(f"right: stored {k_old}/{len(olds)}, now {k_new}/{len(news)}")


if __name__ == "__main__":
    cmd, store, out, *rest = sys.argv[1:]
    if cmd == "score":
        score(store, [out, *rest])
    else:
        kw = dict(zip(rest[::2], rest[1::2]))
        only = [int(x) for x in kw["--seeds"].split(",")] if "--seeds" in kw else None
        run(store, out, kw.get("--order", "random"), int(kw.get("--seed", 0)), kw.get("--part", "0/1"), only)
