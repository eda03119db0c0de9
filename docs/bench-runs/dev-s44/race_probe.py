"""Round 1, fold-level, of stored bench cases: does refining the contenders before the race change
the round's group? Threshold proxy: the 5 % floor every threshold is at least (a superset of the
real contenders). Reads TSV lines: seed truth noise_kind."""
import sys, time, json
import numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, _folded
from voe.gap.finder import ALL_EFFECTS
from voe.gap.search import window_gain, gain_lower_bound, choose
from voe.gap.race import refined_race

THR = 0.05
for line in sys.stdin:
    s, truth, nk = line.split()[:3]
    cid = int(s)
    t0 = time.time()
    case = make_case(np.random.default_rng(cid), truth, 1e-3, 12, 3.0, noise_kind=nk)
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
    ff = _folded(p, p.shooter, p.episodes, p.bad, cfg, cid)
    before = ff.heldout_sse(None, None)
    results = {k: ff.fit_candidate(None, e) for k, e in p.candidates.items()}
    gains = {k: window_gain(before, r.window_sse) for k, r in results.items()}
    lower = {k: gain_lower_bound(before, r.window_sse) for k, r in results.items()}
    g0 = choose(gains, lower, THR)
    r2, gains2, lower2, ref = refined_race(ff, results, gains, lower, THR, before, 0.05)
    g1 = choose(gains2, lower2, THR)
    top = sorted(gains, key=lambda k: -gains[k])[:4]
    print(json.dumps({"seed": cid, "truth": truth, "nk": nk, "group0": g0, "group1": g1, "flip": g0[:1] != g1[:1],
                      "changed": g0 != g1, "refined": sorted(ref),
                      "top": [(k, round(gains[k], 4), round(gains2[k], 4)) for k in top],
                      "sec": round(time.time() - t0)}), flush=True)
