"""End-to-end dev probe (PYTHONPATH=<checkout with voe.gap.spare>): run bench cases, print names/verdict/dropped next
to the stored record, and log every call of voe.gap.spare.spare from the search (winner, group, earlier thresholds,
round threshold, and what it returned). A case whose log holds no call that returned a member cannot differ from
main at cb563ba in its search. Reads TSV: seed truth noise_kind. The lines are dev-s43/e2e.py's with a "log" field."""
import sys
from pathlib import Path

import voe.gap.greedy as greedy

LOG = []
_orig = greedy.spare


def spare(fitter, winner, kept, results, thresholds, threshold):
    out = _orig(fitter, winner, kept, results, thresholds, threshold)
    if thresholds and len(kept) > 1:
        LOG.append({"winner": winner, "kept": list(kept), "earlier": [round(x, 4) for x in thresholds],
                    "thr": round(threshold, 4), "spare": None if out is None else
                    {"key": out.key, "parts": list(out.parts), "rises": [round(x, 4) for x in out.rises],
                     "rise": round(out.rise, 4)}})
    return out


greedy.spare = spare
if __name__ == "__main__":  # the case loop is dev-s43's (its lines, plus this log)
    sys.path.insert(0, str(Path(__file__).parent.parent / "dev-s43"))
    import e2e

    e2e.main(extra=lambda: {"log": LOG[:20]}, before_case=LOG.clear)
