"""How many selection windows each stored floor patch is expressed in (``voe.gap.bench.expression``: the patch's
scene against the nominal one, from the same recorded start, RMS difference above 3 noise sigmas), next to the
stored verdict. The selection windows are the finder's (``voe.gap.stages._folded``, same seed), built without the
search.

    python patch_expr.py STORE.jsonl [...]
"""
import json, sys
import numpy as np
from voe.gap.bench import EXPRESSED_Z, make_case
from voe.gap.bench_score import outside_right
from voe.gap.finder import GapFinder
from voe.gap.shooting import Shooter
from voe.gap.stages import GapConfig, _folded, prepare

for path in sys.argv[1:]:
    lines = open(path).read().splitlines()
    run = json.loads(lines[0])
    run = run.get("run", run)
    for ln in lines[1:]:
        r = json.loads(ln)
        if r.get("truth") != "floor_patch":
            continue
        cfg = GapConfig(cross_fit=bool(run.get("cross_fit", False)))
        case = make_case(np.random.default_rng(r["seed"]), "floor_patch", run.get("noise", 1e-3), run.get("episodes", 12),
                         run.get("duration", 3.0), noise_kind=r["noise_kind"])
        p = prepare(case.scene, case.episodes, GapFinder(seed=r["seed"]).effects, cfg)
        wins = _folded(p, p.shooter, p.episodes, p.bad, cfg, r["seed"]).test
        a = p.shooter.simulate_many(wins, None, None)
        b = Shooter(case.sim_scene, p.shooter.episodes, p.shooter.substep, p.shooter.half).simulate_many(wins, None, None)
        rms = np.array([np.sqrt(np.mean(((x - y) * p.shooter.scale[None]) ** 2)) for x, y in zip(a, b, strict=True)])
        k = int(np.sum(rms > EXPRESSED_Z * run.get("noise", 1e-3)))
        print(f"{r['seed']} {r['verdict']:<11} right {outside_right(r)!s:<5} named {','.join(r['names']) or '-':<24} "
              f"expressed {k}/{len(wins)} largest {1e3 * rms.max():.1f} mm", flush=True)
