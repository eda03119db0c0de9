"""Dump the location's window z-scores of stored bench cases: the data's (W,), the clean replicate's (W,) and
the window-local replicates' (R, W), with the case's departure p, for trying other departure statistics
offline (``voe.gap.departure``). The same calls, seeds and order as ``voe.gap.stages.locate_parts``.

    python dump_z.py OUT.npz STORE.jsonl [STORE.jsonl ...] [--clean N]   (out-of-library cases and the first N clean)
"""
import json
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.departure import departure_p, local_replicates
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.synth import null_like
from voe.gap.shooting import Shooter, make_windows
from voe.gap.stages import GapConfig, prepare

args = sys.argv[1:]
n_clean = 30
if "--clean" in args:
    i = args.index("--clean")
    n_clean = int(args[i + 1])
    args = args[:i] + args[i + 2:]
out, stores = args[0], args[1:]
cfg = GapConfig()
rows = {}
for path in stores:
    k = 0
    for ln in open(path):
        r = json.loads(ln)
        if "truth" not in r:
            continue
        clean = r["truth"] == "none"
        if not (r["kind"] == "outside" or (clean and k < n_clean)):
            continue
        k += clean
        seed = int(r["seed"])
        case = make_case(np.random.default_rng(seed), r["truth"], 1e-3, 12, 3.0, noise_kind=r["noise_kind"])
        p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
        rng = np.random.default_rng(seed)
        windows = make_windows(p.episodes, list(range(len(p.episodes))), cfg.locate_window, bad_start=p.bad)
        null_eps = null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi, p.jitter)
        z_null = window_z(Shooter(p.scene, null_eps, p.substep, p.half), windows, p.sigma).max(axis=(1, 2))
        z = window_z(p.shooter, windows, p.sigma).max(axis=(1, 2))
        local = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, jitter=p.jitter)
        dp = departure_p(z, z_null, local)
        rows[str(seed)] = (z, z_null, local, dp, r["truth"], r["noise_kind"], r["verdict"])
        print(seed, r["truth"], r["noise_kind"], r["verdict"], f"departure_p {dp:.4f}", flush=True)
np.savez(out, **{f"{s}_{n}": v for s, row in rows.items() for n, v in zip(("z", "zn", "local"), row[:3], strict=True)},
         meta=np.array(json.dumps({s: row[3:] for s, row in rows.items()})))
