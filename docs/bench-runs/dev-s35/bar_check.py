"""Session 35: the second look's test-gain bar (``voe.gap.check.short_on_test``) on a stored run.

The bar is a filter after the second look, so it can change only a case where the second look
named something with a test-split RMSE reduction under ``GapConfig.second_look_test_gain``. This
reruns, on this checkout's finder, every case of STORE that named something with a stored reduction
under the bar (the record does not say which look named it; the rerun does), and writes what the
finder says now: which look named, the verdict, the names, the drops and their reasons.
Usage: PYTHONPATH=<checkout> python bar_check.py STORE OUT [--jobs 2]
"""
import json
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder


def rerun(r: dict) -> dict:
    case = make_case(np.random.default_rng(r["seed"]), r["truth"], 1e-3, 12, 3.0, noise_kind=r["noise_kind"])
    f = GapFinder(max_effects=3, seed=r["seed"], config=GapConfig()).fit(case.scene, case.episodes)
    return {"seed": r["seed"], "truth": r["truth"], "kind": r["kind"], "noise_kind": r["noise_kind"],
            "stored": {"names": r["names"], "verdict": r["verdict"], "reduction": 1 - r["after"] / r["before"]},
            "second_look": f.first_look_ is not None, "names": [e["name"] for e in f.effects_],
            "verdict": f.verdict_, "located": len(f.located_), "before": f.fit_["before"], "after": f.fit_["after"],
            "dropped": list(f.checked_.dropped)}


if __name__ == "__main__":
    store, out = sys.argv[1], sys.argv[2]
    jobs = int(sys.argv[sys.argv.index("--jobs") + 1]) if "--jobs" in sys.argv else 2
    bar = GapConfig().second_look_test_gain
    rows = [json.loads(line) for line in open(store) if line.startswith('{"seed"')]
    last = {r["seed"]: r for r in rows}  # the last line per seed, as the bench scores
    pick = [r for r in last.values() if r["names"] and r["names"] != ["error"] and r["before"] > 0
            and 1 - r["after"] / r["before"] < bar]
    print(f"{len(pick)} of {len(last)} cases named something with a test reduction under {100 * bar:g} %", flush=True)
    with ProcessPoolExecutor(jobs) as ex, open(out, "a") as fh:
        for res in ex.map(rerun, pick):
            fh.write(json.dumps(res) + "\n")
            fh.flush()
            print(res["seed"], res["truth"], "stored", res["stored"]["names"], f"{100 * res['stored']['reduction']:.1f} %",
                  "-> second look" if res["second_look"] else "-> first look", res["verdict"], res["names"], flush=True)
