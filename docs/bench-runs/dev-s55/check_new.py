"""The landed flight_drift against the harness's hyb on gusts (same fits)."""
import json, sys
import numpy as np
import fdrift as F
from voe.gap import drift as D
from voe.gap.bench import make_case, plan
from voe.gap.prefit import flight_samples, seen_missing
from voe.gap.effects import EFFECTS
from voe.gap.stages import context_for
agree = dis = 0
for sb in map(int, sys.argv[1:]):
    for s, truth, nk, role in plan(130, sb, compound=8, outside=12, clean=0):
        if truth != "gust": continue
        case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind="white")
        eps = case.episodes[:6]
        seen = flight_samples(case.scene, eps, around=True)
        if seen is None or len(seen) < 30: continue
        F.CTX[0] = ctx = context_for(case.scene, eps)
        for name in ("spring_anchor", "point_attractor", "linear_drag", "quadratic_drag", "constant_acceleration"):
            e = EFFECTS.get(name)()
            p = F.best_flight_fit(seen, e, ctx, case.scene)
            new = D.flight_drift(seen, e, p, case.scene, ctx)
            h = F.test(F.unit_table(seen, e, p, case.scene), "both", "hyb")
            ok = (new is None) == (h is None)
            agree += ok; dis += not ok
            if not ok or s in (9260143,): print(s, name, new, h)
print("agree", agree, "disagree", dis)
