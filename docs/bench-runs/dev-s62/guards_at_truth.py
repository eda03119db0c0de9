"""Ask the finder's test-split guards of the truth itself (development only).

For each cycle case of a stored bench run (its own seed, truth and noise kind), the truth's parameters are put
where a fitted model would be, on the finder's first look (three-way split): its test windows, located
threshold and clean replicate. Printed: whether ``voe.gap.carry_over.worse_on_test`` (the median test window z,
then ``deepened``) would drop the truth, each test window's z without and with it, and the test-RMSE gain
(``short_on_test`` asks >= 5 % of a second look's name). A guard that drops the truth itself cannot be met by
any fit, so its drops of right names are the guard's, not the search's.

    PYTHONPATH=<clone> python guards_at_truth.py STORE.jsonl [--seeds a,b] [--part I/N] >> OUT.txt
"""
import json
import sys
import time

import numpy as np

from voe.gap.bench import make_case
from voe.gap.carry_over import worse_on_test
from voe.gap.check import Checked, verify_on_test
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.finder import ALL_EFFECTS
from voe.gap.fit import FitResult
from voe.gap.stages import GapConfig, locate_parts, prepare


def truth_model(case, n_folds):
    parts, params = [], []
    for name, (pv, bodies) in case.true.items():
        eff = EFFECTS.get(name.split("[")[0])
        parts.append(eff(tuple(bodies)) if bodies else eff())
        params.append(np.asarray(pv, float))
    tp = np.concatenate(params)
    return FitResult(EffectSum(tuple(parts)), tp, float("nan"), float("nan"), None, (tp,) * n_folds), tuple(case.true)


def ask(seed, truth, kind):
    t0 = time.time()
    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=kind)
    config = GapConfig()
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
    null_eps, finish = locate_parts(p, config, np.random.default_rng(seed))
    loc = finish()
    model, keys = truth_model(case, max(1, len(p.split.folds)) if p.split.cross_validated else 1)
    ver, note = verify_on_test(p, model, config, loc.z_threshold)
    c = Checked(model, keys, np.zeros(0), np.zeros(0), (), ver, note, np.zeros(0))
    out = worse_on_test(c, p, config, loc.z_threshold, loc.null_episodes, seed)
    why = out.dropped[0]["reason"] if out.model is None else ""
    gain = 1 - ver.rmse_after / ver.rmse_before
    return {"seed": seed, "truth": truth, "kind": kind, "dropped": out.model is None, "why": why,
            "z_thr": round(loc.z_threshold, 2), "z_before": np.round(ver.z_before, 1).tolist(),
            "z_truth": np.round(ver.z_after, 1).tolist(), "test_gain": round(gain, 4),
            "median": [round(ver.median_z_before, 2), round(ver.median_z_after, 2)],
            "elapsed": round(time.time() - t0, 1)}


def main():
    store = sys.argv[1]
    args = dict(zip(sys.argv[2::2], sys.argv[3::2]))
    only = {int(s) for s in args["--seeds"].split(",")} if "--seeds" in args else None
    i, n = map(int, args.get("--part", "0/1").split("/"))
    rows = []
    for ln in open(store).read().split("\n")[1:]:
        if ln.strip():
            r = json.loads(ln)
            if (only and r["seed"] in only) or (not only and r.get("role") == "cycle" and r["truth"] != "none"):
                rows.append((r["seed"], r["truth"], r["noise_kind"], r["found"] == r["truth"]))
    for seed, truth, kind, right in rows[i::n]:
        d = ask(seed, truth, kind)
        d["stored_right"] = right
        print(json.dumps(d), flush=True)


if __name__ == "__main__":
    main()
