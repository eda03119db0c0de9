"""Tabulate e2e.py's JSON lines: case, truth, names now and stored, and each unlimit call
(region winner, its gain, the global form's gain at the region's strength or None if it did not join)."""
import json
import sys

for path in sys.argv[1:]:
    for ln in open(path):
        r = json.loads(ln)
        same = "same" if r["names"] == r["stored"] else "DIFF"
        print(f'{r["case"]} {r["truth"]:28s} {same} now {",".join(r["names"]) or "-"} ({r["verdict"]}) stored '
              f'{",".join(r["stored"] or []) or "-"}; unlimit {r["unlimit"]}; {r["sec"]} s')
