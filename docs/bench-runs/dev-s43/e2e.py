"""End-to-end dev probe of a finder checkout (PYTHONPATH): run bench cases, count one-parameter walks
(voe.gap.fit._walk), print names/verdict/dropped next to the stored record. Reads TSV: seed truth noise_kind."""
import json
import sys
import time

import voe.gap.fit as fit
from voe.gap.bench import run_case

WALKS = []
if hasattr(fit, "_walk"):
    orig = fit._walk
    def walk(fitter, effect, *a, **k):
        out = orig(fitter, effect, *a, **k)
        WALKS.append((effect.name, round(float(a[1]), 5), round(float(out[0][0]), 5)))
        return out
    fit._walk = walk


def main(extra=dict, before_case=lambda: None):
    """Run the cases on stdin; ``extra()`` adds fields to each case's line (``before_case`` runs first:
    dev-s45/e2e_trial.py logs the greedy search's trial tests through them)."""
    stored = {}
    for path in sys.argv[1:]:
        for ln in open(path).read().splitlines()[1:]:
            r = json.loads(ln)
            stored[r["seed"]] = r
    for line in sys.stdin:
        s, t, nk = line.split()[:3]
        WALKS.clear()
        before_case()
        t0 = time.time()
        r = run_case((int(s), t, 1e-3, 3, 12, 3.0, nk))
        old = stored.get(int(s), {})
        same = (r["names"], r["verdict"]) == (old.get("names"), old.get("verdict"))
        print(json.dumps({"seed": int(s), "truth": t, "nk": nk, "names": r["names"], "verdict": r["verdict"],
                          "dropped": r["dropped"], "old_names": old.get("names"), "old_verdict": old.get("verdict"),
                          "old_dropped": old.get("dropped"), "same": same, "n_walks": len(WALKS), "walks": WALKS[:12],
                          **extra(), "sec": round(time.time() - t0)}), flush=True)


if __name__ == "__main__":
    main()
