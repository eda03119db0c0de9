"""The finder count with the change against the stored records of main's code (behaviour of
f3a26f5): dev-s55/finder_count.jsonl and the seed-1829 untouched run's gust records.

usage: python compare.py fc_a.jsonl fc_b.jsonl
"""
import json
import sys

HERE = __file__.rsplit("/", 1)[0] or "."
stored = {}
for f in (f"{HERE}/../dev-s55/finder_count.jsonl", f"{HERE}/../gap_bench_s56_seed1829.jsonl"):
    for line in open(f):
        r = json.loads(line)
        if "seed" in r:
            stored[r["seed"]] = r
KEYS = ("found", "names", "verdict", "located")
same, changed = 0, []
for f in sys.argv[1:]:
    for line in open(f):
        r = json.loads(line)
        old = stored[r["seed"]]
        if all(r[k] == old[k] for k in KEYS):
            same += 1
        else:
            changed.append(r["seed"])
            print(r["seed"], r["truth"], " was", {k: old[k] for k in KEYS}, "\n         now", {k: r[k] for k in KEYS},
                  "dropped", r["dropped"])
print(f"identical {same}, changed {len(changed)}: {changed}")
