"""End-to-end dev probe (PYTHONPATH=<checkout>): run bench cases, print names/verdict/dropped next to the stored
record, and count the calls where a trial's test could see a race's refined fit: Trial.confirmed,
Trial.mostly_better and _pair_after_trial when the trial's round (or the confirming round) had refined
contenders. A case with 0 such calls could not differ between 9744e76 and 3d1a337. Reads TSV: seed truth noise_kind.
The lines are dev-s43/e2e.py's with a "log" field (session 45's e2e_trial.jsonl came from a first version that
printed the same fields but n_walks, walks and old_dropped)."""
import importlib.util
from pathlib import Path

import voe.gap.greedy as greedy
import voe.gap.race as race

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
if __name__ == "__main__":  # the case loop is dev-s43's (its lines, plus this log)
    spec = importlib.util.spec_from_file_location("e2e", Path(__file__).parent.parent / "dev-s43" / "e2e.py")
    e2e = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(e2e)
    e2e.main(extra=lambda: {"log": LOG[:40]}, before_case=LOG.clear)
