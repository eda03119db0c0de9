"""Round 1 of a case, fold-level: unrefined and refined gains of named candidates (race before/after refine)."""
import sys, time, json
import numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare, _folded
from voe.gap.finder import ALL_EFFECTS
from voe.gap.search import window_gain

cid, truth = int(sys.argv[1]), sys.argv[2]
names = sys.argv[3].split(",")
case = make_case(np.random.default_rng(cid), truth, 1e-3, 12, 3.0, noise_kind="white")
cfg = GapConfig()
p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
ff = _folded(p, p.shooter, p.episodes, p.bad, cfg, cid)
before = ff.heldout_sse(None, None)
for n in names:
    t0 = time.time()
    r = ff.fit_candidate(None, p.candidates[n])
    g = window_gain(before, r.window_sse)
    rr = ff.refine(r)
    g2 = window_gain(before, rr.window_sse)
    print(json.dumps({"case": cid, "cand": n, "gain": round(g, 4), "refined": round(g2, 4),
                      "params": np.round(r.params, 4).tolist(), "ref_params": np.round(rr.params, 4).tolist(),
                      "true": str(case.true)[:120], "sec": round(time.time() - t0)}), flush=True)
