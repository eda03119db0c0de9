"""Run bench cases (``voe.gap.bench.run_case``, the bench's own record) on the current code and print
each beside its stored record of a finished run (development only).

    PYTHONPATH=<clone> python cases.py STORE.jsonl SEED [SEED ...] > out.jsonl
"""
import json
import sys
import time

from voe.gap.bench import run_case

store, seeds = sys.argv[1], [int(s) for s in sys.argv[2:]]
old = {}
for line in open(store):
    d = json.loads(line)
    if "truth" in d:
        old[d["seed"]] = d
for s in seeds:
    o = old[s]
    t0 = time.time()
    r = run_case((s, o["truth"], 1e-3, 3, 12, 3.0, o["noise_kind"]))
    r["elapsed"] = round(time.time() - t0, 1)
    r["stored"] = {k: o[k] for k in ("names", "verdict", "located")}
    print(json.dumps(r), flush=True)
    print(f"{s} {o['truth']} {o['noise_kind']}: stored {o['names']} {o['verdict']} -> now {r['names']} {r['verdict']} "
          f"({r['elapsed']} s)", file=sys.stderr, flush=True)
