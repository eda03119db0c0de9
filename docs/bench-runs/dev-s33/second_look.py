"""Session 33, development (seed 6774 is development since session 32): would a second look with
cross-fitting rescue the cases the default three-way split named nothing on, and what does it do to
the clean and out-of-library cases that named nothing?

Cases (fixed before any run): every single and out-of-library case of the seed-6774 store that named
nothing (9 singles, all misses; 10 out-of-library), the one clean false discovery (6774301), and 16
clean cases that named nothing, drawn with numpy seed 33 (8 coloured, 8 white). Each is the bench's
own case (``voe.gap.bench.run_case``) with ``cross_fit=True``; output: second_look.jsonl.
Usage: PYTHONPATH=<checkout> python second_look.py
"""
import json
import os
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from voe.gap.bench import run_case

HERE = os.path.dirname(os.path.abspath(__file__))
STORE = os.path.join(HERE, "..", "gap_bench_s32_seed6774.jsonl")
rows = [json.loads(line) for line in open(STORE)][1:]
pick = [r for r in rows if r["truth"] != "none" and not r["names"] and r["kind"] in ("single", "outside")]
pick += [r for r in rows if r["seed"] == 6774301]
clean = [r for r in rows if r["truth"] == "none" and not r["names"] and r["seed"] != 6774301]
rng = np.random.default_rng(33)
for nk in ("coloured", "white"):
    pool = [r for r in clean if r["noise_kind"] == nk]
    pick += [pool[i] for i in sorted(rng.choice(len(pool), 8, replace=False))]
args = [(r["seed"], r["truth"], 1e-3, 3, 12, 3.0, r["noise_kind"], True) for r in pick]
before = {r["seed"]: r for r in pick}
out = os.path.join(HERE, "second_look.jsonl")
done = {json.loads(line)["seed"] for line in open(out)} if os.path.exists(out) else set()
with ProcessPoolExecutor(2) as ex, open(out, "a") as fh:
    for r in ex.map(run_case, [a for a in args if a[0] not in done]):
        b = before[r["seed"]]
        r["default"] = {"names": b["names"], "verdict": b["verdict"], "expressed": b.get("expressed")}
        fh.write(json.dumps(r) + "\n")
        fh.flush()
        print(r["seed"], r["truth"], r["noise_kind"], "default:", b["verdict"], "->", r["verdict"], r["names"],
              "expressed", r.get("expressed"), flush=True)
