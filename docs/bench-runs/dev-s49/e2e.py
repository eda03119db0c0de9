"""Run the finder (PYTHONPATH's checkout) on SEED:TRUTH:NOISE lines from stdin; one JSON line each with the
names, verdict, how many fits the guessed-start screen moved, and the stored names. Diagnosis only."""
import glob, json, os, sys, time
import numpy as np
import voe.gap.fit as fm
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder
stored = {}  # case seed -> its record in the stored untouched runs beside this folder
for path in sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "gap_bench_*.jsonl"))):
    for ln in open(path).read().splitlines()[1:]:
        r = json.loads(ln)
        stored[str(r["seed"])] = r
moved = []
if hasattr(fm.Fitter, "_screen_guess"):
    orig = fm.Fitter._screen_guess
    def scr(self, effect, x0, lo, hi, scale):
        x = orig(self, effect, x0, lo, hi, scale)
        if x is not x0:
            moved.append([p.name for p in effect.parts])
        return x
    fm.Fitter._screen_guess = scr
for line in sys.stdin:
    if not line.strip(): continue
    seed, truth, nk = line.strip().split(":"); t0 = time.time(); moved.clear()
    case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
    f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
    s = stored.get(seed, {})
    print(json.dumps({"case": int(seed), "truth": truth, "names": [e["name"] for e in f.effects_], "verdict": f.verdict_,
                      "stored": s.get("names"), "stored_verdict": s.get("verdict"), "moved": len(moved),
                      "moved_parts": sorted({"+".join(m) for m in moved}), "sec": round(time.time() - t0)}), flush=True)
