"""Session 34, development (seed 6774): where does the model's own replicate bar in
``voe.gap.check.deepened`` change a decision, and what do those cases end as?

Cases (fixed before any run): every case of the seed-6774 store (session 32, one look, the code
before the second look) that named nothing and dropped something: the only cases where ``deepened``
can have dropped the final model. Four out-of-library cases first (the first start), then the clean
ones, the single truths and the other out-of-library cases (restarted for time: clean ones first).
Each is the bench's own case (``voe.gap.bench.run_case``, default finder: the second look on) on this
checkout; ``deepened`` is wrapped to record every test window that the clean bar alone would
have blamed, with the model's own replicates' median z and whether they excused it. A case with
no excused window has the same answer as without the new bar. Output: deepen_check.jsonl.
Usage: PYTHONPATH=<checkout> python deepen_check.py [--limit N]
"""
import dataclasses
import json
import os
import sys
from concurrent.futures import ProcessPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
STORE = os.path.join(HERE, "..", "gap_bench_s32_seed6774.jsonl")


def _case(args):
    import voe.gap.check as check
    from voe.gap.bench import run_case

    events = []
    original = check.deepened

    def wrapped(p, model, config, z_thr, null_episodes, ver=None, seed=0):
        old = original(p, model, dataclasses.replace(config, deepen_replicates=0), z_thr, null_episodes, ver, seed)
        new = original(p, model, config, z_thr, null_episodes, ver, seed)
        kept = {(round(b, 6), round(a, 6)) for b, a, _, _ in new}
        events.append({"model": [type(e).__name__ for e in getattr(model.effect, "parts", [model.effect])],
                       "params": [float(x) for x in model.params],
                       "clean_bar_blamed": [[b, a, n] for b, a, n, _ in old],
                       "still_blamed": [[b, a, n, m] for b, a, n, m in new],
                       "excused": [[b, a] for b, a, _, _ in old if (round(b, 6), round(a, 6)) not in kept]})
        return new

    check.deepened = wrapped
    r = run_case(args)
    r["deepened_events"] = events
    return r


if __name__ == "__main__":
    rows = [json.loads(line) for line in open(STORE)][1:]
    pick = [r for r in rows if not r["names"] and r.get("dropped")]
    order = {"outside": 2, "single": 1}
    pick.sort(key=lambda r: (order[r["kind"]] if r["truth"] != "none" else 0, r["seed"]))
    if "--limit" in sys.argv:
        pick = pick[:int(sys.argv[sys.argv.index("--limit") + 1])]
    args = [(r["seed"], r["truth"], 1e-3, 3, 12, 3.0, r["noise_kind"], False) for r in pick]
    before = {r["seed"]: r for r in pick}
    out = os.path.join(HERE, "deepen_check.jsonl")
    done = {json.loads(line)["seed"] for line in open(out)} if os.path.exists(out) else set()
    with ProcessPoolExecutor(2) as ex, open(out, "a") as fh:
        for r in ex.map(_case, [a for a in args if a[0] not in done]):
            b = before[r["seed"]]
            r["stored"] = {"names": b["names"], "verdict": b["verdict"], "dropped": b.get("dropped")}
            fh.write(json.dumps(r) + "\n")
            fh.flush()
            ex_ = [e for e in r["deepened_events"] if e["excused"]]
            print(r["seed"], r["truth"], r["noise_kind"], "stored:", b["verdict"], b["names"], "->", r["verdict"],
                  r["names"], "| deepened calls", len(r["deepened_events"]), "excused", ex_, flush=True)
