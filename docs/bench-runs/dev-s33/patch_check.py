"""Session 33, development: main's finder with the second look and the per-contact
``friction_region`` (floor coefficient set in the contact's pre_solve, interval starts on a
12-step grid, screened on every fitting window), on cases fixed before any run:
the floor patches of seeds 6774, 2307 and 2250 (i = 138, 140, ..., 148), the gusts of 6774
(139, ..., 149), the ten friction singles of 6774's cycle, and twelve clean cases (the first six
coloured and six white of second_look.py's draw) plus 6774301. All development seeds.
Output: patch_check.jsonl, each line the bench's own result (``run_case``) and the stored
run's names and verdict for that case. Usage: PYTHONPATH=<checkout> python patch_check.py
"""
import json
import os
from concurrent.futures import ProcessPoolExecutor

from voe.gap.bench import run_case

HERE = os.path.dirname(os.path.abspath(__file__))
STORES = {6774: "gap_bench_s32_seed6774.jsonl", 2307: "gap_bench_s27_seed2307.jsonl", 2250: "gap_bench_s25_seed2250.jsonl"}
stored = {}
for seed, name in STORES.items():
    for line in open(os.path.join(HERE, "..", name)):
        r = json.loads(line)
        if "seed" in r and isinstance(r["seed"], int):
            stored[r["seed"]] = r
pick = [s * 1000 + i for s in STORES for i in range(138, 150, 2)]
pick += [6774000 + i for i in range(139, 150, 2)]
pick += sorted(s for s, r in stored.items() if s // 1000 == 6774 and r["truth"] == "friction" and r.get("role") == "cycle")
clean = [json.loads(line) for line in open(os.path.join(HERE, "second_look.jsonl"))]
pick += [r["seed"] for r in clean if r["truth"] == "none" and r["noise_kind"] == "coloured"][:6]
pick += [r["seed"] for r in clean if r["truth"] == "none" and r["noise_kind"] == "white" and r["seed"] != 6774301][:6]
pick += [6774301]
# run order (changed after the first 10 cases, for time): clean, friction singles, gusts, then the rest of the patches
order = {"none": 0, "friction": 1, "gust": 2, "floor_patch": 3}
pick = sorted(pick, key=lambda s: order[stored[s]["truth"]])
args = [(s, stored[s]["truth"], 1e-3, 3, 12, 3.0, stored[s]["noise_kind"]) for s in pick]
out = os.path.join(HERE, "patch_check.jsonl")
done = {json.loads(line)["seed"] for line in open(out)} if os.path.exists(out) else set()
with ProcessPoolExecutor(2) as ex, open(out, "a") as fh:
    for r in ex.map(run_case, [a for a in args if a[0] not in done]):
        b = stored[r["seed"]]
        r["stored"] = {"names": b["names"], "verdict": b["verdict"]}
        fh.write(json.dumps(r) + "\n")
        fh.flush()
        print(r["seed"], r["truth"], r["noise_kind"], "stored:", b["verdict"], b["names"], "->", r["verdict"], r["names"],
              flush=True)
