"""The truth's own window-local replicates in the test windows where ``deepened`` drops the truth (development
only): every replicate's z, not only their median, for 10 and 40 draws.

    PYTHONPATH=<clone> python reps_at_truth.py STORE.jsonl SEED [SEED ...]
"""
import json
import sys

import numpy as np

import voe.gap.carry_over as co
from guards_at_truth import ask

calls = []
orig = co.local_replicates


def spy(*a, **k):
    z = orig(*a, **k)
    calls.append(np.asarray(z).ravel())
    return z


co.local_replicates = spy
store, seeds = sys.argv[1], {int(s) for s in sys.argv[2:]}
for ln in open(store).read().split("\n")[1:]:
    if not ln.strip():
        continue
    r = json.loads(ln)
    if r["seed"] not in seeds:
        continue
    calls.clear()
    d = ask(r["seed"], r["truth"], r["noise_kind"])
    print(r["seed"], r["truth"], "dropped" if d["dropped"] else "kept", d["why"][:120])
    for z in calls:
        print("   replicates (10):", np.round(np.sort(z), 1).tolist())
    from voe.gap.stages import GapConfig
    import dataclasses
    orig_cfg = GapConfig
    calls.clear()
    co_cfg = dataclasses.replace(GapConfig(), deepen_replicates=40)
    import guards_at_truth as g
    g.GapConfig = lambda: co_cfg
    d = ask(r["seed"], r["truth"], r["noise_kind"])
    g.GapConfig = orig_cfg
    for z in calls:
        print("   replicates (40):", np.round(np.sort(z), 1).tolist())
