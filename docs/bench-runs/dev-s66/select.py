"""Cases of a finished store for session 66's paired development benches (development only).

    python select.py STORE drops        # cases whose line drops a name (the check's path of s65b)
    python select.py STORE later        # cases whose search fitted a later round's null (round 2 on: s66)
    python select.py STORE random N S   # N other cases drawn with seed S (neither of the above)
Prints the seeds comma-separated (pair.py --seeds).
"""
import json
import sys

import numpy as np


def records(path):
    out = []
    with open(path) as f:
        for ln in f:
            try:
                d = json.loads(ln)
            except json.JSONDecodeError:
                continue
            if "truth" in d:
                out.append(d)
    return out


def later(d):
    return len(d["rounds"]) >= 2 and any(r[2] is not None for r in d["rounds"][1:])


recs = records(sys.argv[1])
how = sys.argv[2]
if how == "drops":
    seeds = [d["seed"] for d in recs if d["dropped"]]
elif how == "later":
    seeds = [d["seed"] for d in recs if later(d)]
else:
    n, s = int(sys.argv[3]), int(sys.argv[4])
    rest = [d["seed"] for d in recs if not d["dropped"] and not later(d)]
    seeds = sorted(np.random.default_rng(s).choice(rest, size=min(n, len(rest)), replace=False).tolist())
print(",".join(map(str, seeds)))
