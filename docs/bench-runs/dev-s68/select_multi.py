"""Cases of a finished store for session 68's paired development bench (development only): those whose search
ended with two or more round winners, the only models the re-selection asks again (``voe.gap.reselect``), so
the only cases that asking every candidate of a round can change.

    PYTHONPATH=<clone> python select_multi.py STORE   # prints the seeds comma-separated (dev-s61/pair.py --seeds), and counts
"""
import os
import sys
from collections import Counter

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "dev-s61"))
from pair import stored  # noqa: E402  the paired bench's own reader of a store (last record per seed)

recs = list(stored(sys.argv[1]).values())
multi = [d for d in recs if sum(r[0] is not None for r in d["rounds"]) >= 2]
print(f"# {len(multi)} of {len(recs)} cases with two or more round winners; by kind "
      f"{dict(Counter(d['kind'] for d in multi))}", file=sys.stderr)
print(",".join(str(d["seed"]) for d in sorted(multi, key=lambda d: d["seed"])))
