"""Run the finder (PYTHONPATH's checkout) on SEED:TRUTH:NOISE lines from stdin; one JSON line each with the
names, verdict, the stored names, and each call of ``voe.gap.greedy._unconfirmed`` (where the checkout has it):
the trial's winner and the refusing winner (None: nothing confirmed it) and whether the trial was kept.
Where no call has a refusing winner, trial-refused.patch cannot have changed the case. Diagnosis only."""
import glob
import json
import os
import sys
import time

import numpy as np

import voe.gap.greedy as gm
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder

stored = {}
for path in sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "gap_bench_*.jsonl"))):
    for ln in open(path).read().splitlines()[1:]:
        r = json.loads(ln)
        stored[str(r["seed"])] = r
calls = []
if hasattr(gm, "_unconfirmed"):
    orig = gm._unconfirmed

    def wrapped(fitter, trial, rounds, current, keys, by_pair, max_effects, q, n_jobs, by=None):
        out = orig(fitter, trial, rounds, current, keys, by_pair, max_effects, q, n_jobs, by)
        calls.append([trial.round.winner, by, list(out[1])])
        return out
    gm._unconfirmed = wrapped
for line in sys.stdin:
    if not line.strip():
        continue
    seed, truth, nk = line.strip().split(":")
    t0 = time.time()
    calls.clear()
    case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
    f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
    s = stored.get(seed, {})
    print(json.dumps({"case": int(seed), "truth": truth, "names": [e["name"] for e in f.effects_], "verdict": f.verdict_,
                      "stored": s.get("names"), "stored_verdict": s.get("verdict"), "unconfirmed": list(calls),
                      "sec": round(time.time() - t0)}), flush=True)
