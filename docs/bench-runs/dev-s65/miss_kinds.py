"""The single-truth misses of every stored untouched run, by kind (session 65; reads the stored .jsonl only).

    python miss_kinds.py   (from this folder)

A miss is "found then dropped" when the case names nothing and its line's dropped list holds the truth; "never
accepted" when it names nothing otherwise; "wrong name" when it names something else. Cycle cases of a library
truth only (the bench's singles, without its `none` cases). The dropped list is the final look's: a truth the
first look dropped before the second look named nothing counts as "never accepted" (2276115, 2276128).
"""
import collections
import glob
import json

tot = collections.Counter()
for f in sorted(glob.glob("../gap_bench_s*_seed*.jsonl")):
    rs = [r for r in map(json.loads, open(f)) if "seed" in r]
    c = collections.Counter()
    for r in rs:
        if r.get("role") != "cycle" or r["truth"] == "none" or r["kind"] != "single":
            continue
        t, names = r["truth"], r["names"]
        if r["found"] == t or (names and names[0].split("[")[0] == t):
            c["right"] += 1
        elif not names and t in [d.split("[")[0] for d in r["dropped"]]:
            c["found then dropped"] += 1
        elif not names:
            c["never accepted"] += 1
        else:
            c["wrong name"] += 1
    print(f.split("/")[-1], dict(c))
    tot += c
print("all", dict(tot))
