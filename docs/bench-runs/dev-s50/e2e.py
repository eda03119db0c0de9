"""Run the finder (PYTHONPATH's checkout) on SEED:TRUTH:NOISE lines from stdin; one JSON line each with the
names, verdict, the stored names, and (where the checkout has it) each call of ``unlimited_member``: the
region winner and whether its global form at the region's strength joined. Diagnosis only."""
import glob, json, os, sys, time
import numpy as np
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder
import voe.gap.greedy as gm
stored = {}  # case seed -> its record in the stored untouched runs beside this folder
for path in sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "gap_bench_*.jsonl"))):
    for ln in open(path).read().splitlines()[1:]:
        r = json.loads(ln)
        stored[str(r["seed"])] = r
calls = []
if hasattr(gm, "unlimited_member"):
    orig = gm.unlimited_member
    def um(fitter, winner, results, gains, *a):
        out = orig(fitter, winner, results, gains, *a)
        calls.append([winner, round(100 * gains[winner], 1), None if out is None else round(100 * out[1], 1)])
        return out
    gm.unlimited_member = um
for line in sys.stdin:
    if not line.strip(): continue
    seed, truth, nk = line.strip().split(":"); t0 = time.time(); calls.clear()
    case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
    f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
    s = stored.get(seed, {})
    print(json.dumps({"case": int(seed), "truth": truth, "names": [e["name"] for e in f.effects_], "verdict": f.verdict_,
                      "stored": s.get("names"), "stored_verdict": s.get("verdict"), "unlimit": list(calls),
                      "sec": round(time.time() - t0)}), flush=True)
