"""Rerun chosen cases of stored bench runs with this checkout's finder; print stored vs new.
Usage: PYTHONPATH=<checkout> python recheck.py OUT STORE:SEED[,SEED...] [...] [--jobs 2]"""
import json
import os
import sys
from concurrent.futures import ProcessPoolExecutor

from voe.gap.bench import run_case

if __name__ == "__main__":
    out = sys.argv[1]
    jobs = int(sys.argv[sys.argv.index("--jobs") + 1]) if "--jobs" in sys.argv else 2
    old = {}
    for arg in (a for a in sys.argv[2:] if ":" in a):
        store, seeds = arg.split(":")
        recs = {}
        for line in open(store).read().splitlines()[1:]:
            if line.startswith('{"seed"') and line.endswith("}"):
                r = json.loads(line)
                recs[r["seed"]] = r
        for s in seeds.split(","):
            old[int(s)] = recs[int(s)]
    done = {json.loads(x)["seed"] for x in open(out)} if os.path.exists(out) else set()
    args = [(s, r["truth"], 1e-3, 3, 12, 3.0, r["noise_kind"]) for s, r in old.items() if s not in done]
    with ProcessPoolExecutor(jobs) as ex, open(out, "a") as fh:
        for new in ex.map(run_case, args):
            o = old[new["seed"]]
            new["stored"] = {k: o[k] for k in ("names", "verdict", "before", "after", "dropped")}
            fh.write(json.dumps(new) + "\n")
            fh.flush()
            def red(r):
                return 100 * (1 - r["after"] / r["before"]) if r["before"] else float("nan")
            print(new["seed"], new["truth"], new["noise_kind"], "stored", o["names"], o["verdict"], f"{red(o):.1f} %",
                  "->", new["names"], new["verdict"], f"{red(new):.1f} %", "dropped", new["dropped"],
                  "same" if (o["names"], o["verdict"]) == (new["names"], new["verdict"]) else "CHANGED", flush=True)
