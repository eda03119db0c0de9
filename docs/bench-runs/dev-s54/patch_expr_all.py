"""As patch_expr.py, over the location's 1-s windows of every episode (``voe.gap.stages.locate_parts``; not only
the finder's selection windows), for the stored floor patches (all, or those given by seed): does the patch act
anywhere in the recordings, and in how many windows?

    python patch_expr_all.py STORE.jsonl [SEED ...]
"""
import json, sys
import numpy as np
from voe.gap.bench import EXPRESSED_Z, make_case
from voe.gap.finder import GapFinder
from voe.gap.shooting import Shooter, make_windows
from voe.gap.stages import GapConfig, prepare

lines = open(sys.argv[1]).read().splitlines()
run = json.loads(lines[0])["run"]
want = set(map(int, sys.argv[2:]))
for ln in lines[1:]:
    r = json.loads(ln)
    if r.get("truth") != "floor_patch" or (want and r["seed"] not in want):
        continue
    cfg = GapConfig()
    case = make_case(np.random.default_rng(r["seed"]), "floor_patch", run["noise"], run["episodes"], run["duration"],
                     noise_kind=r["noise_kind"])
    p = prepare(case.scene, case.episodes, GapFinder(seed=r["seed"]).effects, cfg)
    wins = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
    a = p.shooter.simulate_many(wins, None, None)
    b = Shooter(case.sim_scene, p.shooter.episodes, p.shooter.substep, p.shooter.half).simulate_many(wins, None, None)
    rms = np.array([np.sqrt(np.mean(((x - y) * p.shooter.scale[None]) ** 2)) for x, y in zip(a, b, strict=True)])
    k = int(np.sum(rms > EXPRESSED_Z * run["noise"]))
    print(f"{r['seed']} {r['verdict']:<11} {'-' if not r['names'] else r['names'][0]:<16} location windows: expressed {k}/{len(wins)} largest {1e3 * rms.max():.1f} mm "
          f"(patch x {case.true['friction_region'][0][1]:.2f}-{case.true['friction_region'][0][2]:.2f})", flush=True)
