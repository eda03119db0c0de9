"""Session 35: the second look's test-gain bar (``voe.gap.carry_over.short_on_test``) on a stored run.

The bar is a filter after the second look, so it can change only a case where the second look
named something with a test-split RMSE reduction under ``GapConfig.second_look_test_gain``. This
reruns, with the bench's own ``voe.gap.bench.run_case`` on this checkout's finder, every case of
STORE that named something with a stored reduction under the bar, and appends each new record (with
the stored one under ``"stored"``) to OUT. A case whose names are gone was dropped by the bar (only
the second look is asked); one whose names stay was named by the first look or passed.
With ``--merge MERGED``: also writes STORE with those cases' records replaced by the new ones, which
``bench/gap_bench.py --score-only --results MERGED`` scores as this checkout's finder on the run:
every other case's record is what this finder gives too, since nothing before the bar changed.
Usage: PYTHONPATH=<checkout> python bar_check.py STORE OUT [--jobs 2] [--merge MERGED]
"""
import json
import os
import sys
from concurrent.futures import ProcessPoolExecutor

from voe.gap.bench import run_case
from voe.gap.stages import GapConfig

if __name__ == "__main__":
    store, out = sys.argv[1], sys.argv[2]
    opt = dict(zip(sys.argv[3::2], sys.argv[4::2], strict=False))
    bar = GapConfig().second_look_test_gain
    lines = open(store).read().splitlines()
    last = {}
    for line in lines[1:]:
        if line.startswith('{"seed"') and line.endswith("}"):
            r = json.loads(line)
            last[r["seed"]] = r  # the last line per seed, as the bench scores
    pick = [r for r in last.values() if r["names"] and r["names"] != ["error"] and r["before"] > 0
            and 1 - r["after"] / r["before"] < bar]
    print(f"{len(pick)} of {len(last)} cases named something with a test reduction under {100 * bar:g} %", flush=True)
    done = {json.loads(x)["seed"]: json.loads(x) for x in open(out)} if os.path.exists(out) else {}
    args = [(r["seed"], r["truth"], 1e-3, 3, 12, 3.0, r["noise_kind"]) for r in pick if r["seed"] not in done]
    with ProcessPoolExecutor(int(opt.get("--jobs", 2))) as ex, open(out, "a") as fh:
        for new in ex.map(run_case, args):
            old = last[new["seed"]]
            new = {**new, "role": old.get("role"), "extra": old.get("extra"),
                   "stored": {"names": old["names"], "verdict": old["verdict"], "before": old["before"],
                              "after": old["after"]}}
            done[new["seed"]] = new
            fh.write(json.dumps(new) + "\n")
            fh.flush()
            print(new["seed"], new["truth"], new["noise_kind"], "stored", old["names"], old["verdict"],
                  f"{100 * (1 - old['after'] / old['before']):.1f} % ->", new["names"], new["verdict"],
                  "dropped", new["dropped"], flush=True)
    if "--merge" in opt:
        tmp = opt["--merge"] + ".tmp"
        with open(tmp, "w") as fh:
            fh.write(lines[0] + "\n")
            for r in last.values():
                new = done.get(r["seed"])
                fh.write(json.dumps({k: v for k, v in new.items() if k != "stored"} if new else r) + "\n")
        os.replace(tmp, opt["--merge"])
        print(f"merged: {opt['--merge']} ({sum(s in done for s in last)} of {len(last)} records replaced)")
