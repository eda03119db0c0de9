"""End-to-end dev probe (PYTHONPATH=<checkout>): run bench cases, print names/verdict/dropped next to the stored
record, and count the calls where a trial's test could see a race's refined fit: Trial.confirmed,
Trial.mostly_better and _pair_after_trial when the trial's round (or the confirming round) had refined
contenders. A case with 0 such calls could not differ between 9744e76 and 3d1a337. Reads TSV: seed truth noise_kind."""
import json, sys, time
import voe.gap.greedy as greedy
import voe.gap.race as race
from voe.gap.bench import run_case

LOG = []
_orig_race = race.refined_race


def refined_race(*a, **k):
    out = _orig_race(*a, **k)
    LOG.append(("race", sorted(out[2])))
    return out


greedy.refined_race = refined_race
_orig_conf = greedy.Trial.confirmed


def confirmed(self, after_sse, q):
    ok = _orig_conf(self, after_sse, q)
    LOG.append(("confirmed", ok, self.round.winner))
    return ok


greedy.Trial.confirmed = confirmed
_orig_mb = greedy.Trial.mostly_better.fget
greedy.Trial.mostly_better = property(lambda self: LOG.append(("mostly_better", self.round.winner)) or _orig_mb(self))
_orig_pat = greedy._pair_after_trial


def pair_after_trial(fitter, trial, *a, **k):
    LOG.append(("pair_after_trial", trial.round.winner))
    return _orig_pat(fitter, trial, *a, **k)


greedy._pair_after_trial = pair_after_trial
stored = {}
for path in sys.argv[1:]:
    for l in open(path).read().splitlines()[1:]:
        r = json.loads(l); stored[r["seed"]] = r
for line in sys.stdin:
    s, t, nk = line.split()[:3]
    LOG.clear()
    t0 = time.time()
    r = run_case((int(s), t, 1e-3, 3, 12, 3.0, nk))
    old = stored.get(int(s), {})
    same = (r["names"], r["verdict"]) == (old.get("names"), old.get("verdict"))
    print(json.dumps({"seed": int(s), "truth": t, "nk": nk, "names": r["names"], "verdict": r["verdict"],
                      "dropped": r["dropped"], "old_names": old.get("names"), "old_verdict": old.get("verdict"),
                      "same": same, "log": LOG[:40], "sec": round(time.time() - t0)}), flush=True)
