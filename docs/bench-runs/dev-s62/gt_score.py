"""Summarise guards_at_truth.py's output (development only): how often each test-split guard would drop the
truth itself, by run, and beside whether the run named the case right.

    python gt_score.py gt_*.jsonl
"""
import json
import sys
from collections import Counter

rows = [json.loads(ln) for f in sys.argv[1:] for ln in open(f) if ln.strip()]
kind = Counter()
for r in rows:
    why = r["why"]
    g = "median" if "median window z" in why else "deepened" if "itself a departure" in why else "kept"
    r["guard"] = g
    kind[g, r["stored_right"]] += 1
n = len(rows)
print(f"{n} cycle cases; the truth itself dropped by a test-split guard: {sum(r['dropped'] for r in rows)}/{n}")
for g in ("median", "deepened"):
    print(f"  {g}: {kind[g, True] + kind[g, False]} (of them named right by the run anyway: {kind[g, True]}; "
          f"missed: {kind[g, False]})")
small = [r for r in rows if r["test_gain"] < 0.05]
print(f"test-RMSE gain at the truth below 5 % (short_on_test's bar for a second look's name): {len(small)}/{n}; "
      f"named right by the run anyway: {sum(r['stored_right'] for r in small)}")
print("missed by the run:", sum(not r["stored_right"] for r in rows))
for r in rows:
    if r["dropped"] or not r["stored_right"]:
        print(r["seed"], r["truth"], "right" if r["stored_right"] else "MISSED", r["guard"], "gain", r["test_gain"],
              "z", r["z_before"], "->", r["z_truth"], "|", r["why"][:160])
