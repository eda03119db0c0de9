"""Every ``deepened`` question the finder asks on one bench case, with all of the model's own replicates (not only
their median): the rise, the bars, what a bar at the replicates' 90th percentile or maximum would say, and
the window's z with each model's start velocity refitted under it (``startfit.py``; development only).

    PYTHONPATH=<clone> python deep_tails.py SEED TRUTH NOISE_KIND
"""
import sys
import time

import numpy as np
from startfit import refit, sigma_v, z_of

import voe.gap.carry_over as co
from voe.gap.bench import make_case
from voe.gap.departure import local_replicates
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig


def deepened(p, model, config, z_thr, null_episodes, ver=None, seed=0):
    pairs = co.heldout_pairs(p, model, config)[0]
    if not pairs:
        return []
    ver = ver if ver is not None and ver.z_before else co.verify_on_test(p, model, config, z_thr)[0]
    zb, za = np.asarray(ver.z_before), np.asarray(ver.z_after)
    null = co.Shooter(p.scene, null_episodes, p.substep, p.half)
    zn = co.window_z(null, [w for w, _ in pairs], p.sigma).max(axis=(1, 2))
    rise = np.sqrt(np.maximum(0.0, za ** 2 - zb ** 2))
    bar = config.deepen_factor * np.maximum(zn, z_thr)
    grown = za > config.deepen_growth * zb
    out = []
    rng = np.random.default_rng(seed)
    names = "+".join(q.name for q in model.effect.parts)
    print(f"  deepened? model {names} z_thr {z_thr:.2f}; windows zb {np.round(zb, 1).tolist()} za {np.round(za, 1).tolist()}"
          f" rise {np.round(rise, 1).tolist()} clean-bar {np.round(bar, 1).tolist()}", flush=True)
    for i in np.flatnonzero((rise > bar) & grown):
        w, params = pairs[i]
        reps = np.asarray(local_replicates(p.shooter, [w], p.sigma, p.phi, rng, config.deepen_replicates,
                                           p.jitter, model.effect, params)).ravel()
        zm = float(np.median(reps))
        drop = rise[i] > config.deepen_factor * max(zm, zn[i], z_thr)
        q90 = float(np.quantile(reps, 0.9))
        mx = float(reps.max())
        print(f"    window {i}: zb {zb[i]:.1f} za {za[i]:.1f} rise {rise[i]:.1f}; replicates {np.round(np.sort(reps), 1).tolist()}"
              f"; median bar {config.deepen_factor * max(zm, zn[i], z_thr):.1f} -> {'DROP' if drop else 'spare'};"
              f" q90 bar {config.deepen_factor * max(q90, zn[i], z_thr):.1f} -> {'DROP' if rise[i] > config.deepen_factor * max(q90, zn[i], z_thr) else 'spare'};"
              f" max bar {config.deepen_factor * max(mx, zn[i], z_thr):.1f} -> {'DROP' if rise[i] > config.deepen_factor * max(mx, zn[i], z_thr) else 'spare'}",
              flush=True)
        sh = p.shooter
        sv = sigma_v(sh.half, float(np.median(np.diff(sh.episodes[w.ep].t))), p.sigma)
        zb_r = z_of(sh, w, refit(sh, w, None, None, p.sigma, sv)[0], p.sigma)
        za_r = z_of(sh, w, refit(sh, w, model.effect, params, p.sigma, sv)[0], p.sigma)
        print(f"      start refitted under each: zb {zb_r:.1f} za {za_r:.1f} rise {np.sqrt(max(0.0, za_r ** 2 - zb_r ** 2)):.1f}"
              f" against the same bar {config.deepen_factor * max(zm, zn[i], z_thr):.1f}", flush=True)
        if drop:
            out.append((float(zb[i]), float(za[i]), float(zn[i]), zm))
    return out


co.deepened = deepened
s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
t0 = time.time()
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
f = GapFinder(max_effects=3, seed=s, config=GapConfig()).fit(case.scene, case.episodes)
print(s, truth, kind, "verdict", f.verdict_, [(e["name"], {k: round(v, 4) for k, v in e["params"].items()})
                                              for e in f.effects_], f"{time.time() - t0:.0f} s")
for d in f.checked_.dropped:
    print("  drop", d["effect"], "|", d["reason"][:300])
