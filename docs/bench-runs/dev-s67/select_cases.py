"""Cases of a finished store for session 67's paired development bench (development only): the union of
the cases whose line drops a name (the check's path that s65b's earlier model changes) and the cases whose
search accepted a mass in some round (those a later round could offer the other body's mass: mass_ratio).

    PYTHONPATH=<clone> python select_cases.py STORE   # prints the seeds comma-separated (dev-s61/pair.py --seeds), and counts
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "dev-s61"))
from pair import stored  # noqa: E402  the paired bench's own reader of a store (last record per seed)


def with_mass(d):
    return any(r[0] and r[0].startswith("mass[") or any(g.startswith("mass[") for g in r[1]) for r in d["rounds"])


recs = list(stored(sys.argv[1]).values())
drops = {d["seed"] for d in recs if d["dropped"]}
mass = {d["seed"] for d in recs if with_mass(d)}
print(f"# drops {len(drops)}, mass {len(mass)}, both {len(drops & mass)}, union {len(drops | mass)}", file=sys.stderr)
print(",".join(str(s) for s in sorted(drops | mass)))
