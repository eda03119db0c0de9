"""Would the search's own earlier model pass the check where the check's refit did not? (session 65, development)

The first look (``second_look=False``) runs as the bench runs it, every model the search accepts recorded (the
greedy loop's ``on_model``). Then each recorded model is asked what the check asks of a model it reports: against
the nominal model on the selection windows (``voe.gap.check.short_of_nominal``, the first round's threshold and
the 5 % quantile) and whether its 95 % interval establishes each part (``model_intervals``, ``established``).
Motivation: 2276115 (a true ``rolling_resistance``): round 1 accepted it, round 2 a stand-in; the check dropped the
stand-in (not established) and the rolling resistance refitted alone failed ``short_of_nominal`` (quantile -2.3 %).

    [LOOK=2] PYTHONPATH=<clone> python earlier_model.py SEED TRUTH NOISE_KIND
LOOK=2: the second look's split (cross-fitted) instead.
"""
import os, sys, time
import numpy as np
import voe.gap.stages as stages
from voe.gap.bench import make_case
from voe.gap.check import model_intervals, short_of_nominal
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig, fit_context
from voe.gap.uncertainty import established

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
seen = []
orig = stages.greedy


def greedy(*a, **k):
    a = list(a)
    inner = a[9] if len(a) > 9 else k.get("on_model")

    def on_model(m):
        seen.append(m)
        if inner is not None:
            inner(m)
    if len(a) > 9:
        a[9] = on_model
    else:
        k["on_model"] = on_model
    return orig(*a, **k)


stages.greedy = greedy
t0 = time.time()
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
cfg = GapConfig(second_look=False, cross_fit=os.environ.get("LOOK") == "2")
f = GapFinder(max_effects=3, seed=s, config=cfg).fit(case.scene, case.episodes)
print(s, truth, kind, "look", os.environ.get("LOOK", "1"), "verdict", f.verdict_,
      [(e["name"], {k: round(v, 4) for k, v in e["params"].items()}) for e in f.effects_],
      [d["effect"] + ": " + d["reason"][:120] for d in f.checked_.dropped], f"{time.time() - t0:.0f} s", flush=True)
p, res = f.problem_, f.search_.result
first = res.rounds[0].threshold if res.rounds else None
ctx = fit_context(p)
for m in seen:
    why = short_of_nominal(m, res.nominal_sse, cfg.min_gain if first is None else first, cfg.gain_lower_q)
    lo, hi = model_intervals(p, p.split.fit, m, ctx, cfg, s)
    print(f"  accepted {[type(e).__name__ for e in m.effect.parts]} params {np.round(m.params, 4).tolist()}: "
          f"short_of_nominal {why!r}; interval {np.round(lo, 4).tolist()} .. {np.round(hi, 4).tolist()}, "
          f"established {established(m.effect, lo, hi, ctx)}", flush=True)
