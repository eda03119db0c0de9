"""Session 47: one table row per case of the residual-departure probe's output (``../dev-s46/residual_departure.py``),
with the counts a rule on the tail p would give at a few levels. Usage: PYTHONPATH=<checkout> python table.py FILE.jsonl ...
"""
import json
import sys

from voe.gap.truths import OUTSIDE

rows = [json.loads(line) for f in sys.argv[1:] for line in open(f)]
print("| case | truth -> named | verdict | tail p of each look asked (windows) |")
print("|---|---|---|---|")
for d in rows:
    looks = ", ".join(f"{a['p_tail']:g} ({len(a['z_after'])})" for a in d["asked"]) or "not asked"
    print(f"| {d['case']} | {d['truth']} -> {', '.join(d['names']) or 'nothing'} | {d['verdict']} | {looks} |")


def kind(d: dict) -> str:
    """right (every name in the truth, the whole truth named; out of the library, only names the bench accepts:
    ``voe.gap.truths.OUTSIDE``), partial (a compound named in part), none (nothing named in the end: a look's model
    was dropped later), or wrong."""
    if not d["names"]:
        return "none"
    if d["truth"] in OUTSIDE:
        return "right" if set(d["names"]) <= set(OUTSIDE[d["truth"]]) else "wrong"
    truth, named = set(d["truth"].split("+")), set(d["names"])
    return "right" if named == truth else "partial" if named and named < truth else "wrong"


print()
lowest = [min((a["p_tail"] for a in d["asked"] if a["kept"]), default=1.0) for d in rows]
for alpha in (0.01, 0.005, 0.002):
    print(f"tail p < {alpha:g} in a kept look: " + ", ".join(
        f"{k} {sum(p < alpha for d, p in zip(rows, lowest, strict=True) if kind(d) == k)} of {sum(kind(d) == k for d in rows)}"
        for k in ("right", "partial", "none", "wrong")))
