"""What the second look's test guard (``voe.gap.carry_over.short_on_test``) sees, per test window (session 65,
development only). The whole finder runs as the bench runs it; the guard is wrapped so that, before it decides,
the named model's test windows are simulated with and without it and printed: the guard's own figure (the test
RMSE's fall), the geometric-mean fall of the windows' noise-standardised RMS (the selection statistic's form,
``voe.gap.search.window_gain``), and in how many test windows the model moves the prediction by more than 3
noise sigmas (RMS over the window).

    PYTHONPATH=<clone> python second_look_probe.py SEED TRUTH NOISE_KIND
"""
import sys, time
import numpy as np
import voe.gap.finder as finder_mod
from voe.gap.bench import make_case
from voe.gap.check import heldout_pairs
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig
from voe.gap.verify import _residuals_at

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
orig = finder_mod.short_on_test


def probe(c, p, config, z_thr):
    if c.model is not None:
        pairs, _ = heldout_pairs(p, c.model, config)
        w = [x for x, _ in pairs]
        b = p.shooter.residuals(w, None, None)
        a = _residuals_at(p.shooter, pairs, c.model.effect)
        sb = np.array([np.sum((r / p.sigma[None]) ** 2) for r in b])  # (W,) standardised SSE
        sa = np.array([np.sum((r / p.sigma[None]) ** 2) for r in a])
        n = np.array([r.size for r in b])
        moved = np.array([np.sqrt(np.mean(((ra - rb) / p.sigma[None]) ** 2)) for ra, rb in zip(a, b)])  # (W,)
        lr = 0.5 * np.log(np.maximum(sa, 1e-300) / np.maximum(sb, 1e-300))  # (W,) log RMS ratio
        v = c.verification
        print(f"  second look names {c.keys}: test RMSE {v.rmse_before:.5g} -> {v.rmse_after:.5g} "
              f"({100 * (1 - v.rmse_after / v.rmse_before):.1f} %); geometric window gain {100 * (1 - np.exp(lr.mean())):.1f} %"
              f" over {lr.size} windows; moved > 3 sigma in {int(np.sum(moved > 3))}; log ratios where moved > 1 sigma "
              f"{np.round(lr[moved > 1], 2).tolist()}; window RMS/sigma before {np.round(np.sqrt(sb / n), 1).tolist()}", flush=True)
    return orig(c, p, config, z_thr)


finder_mod.short_on_test = probe
t0 = time.time()
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
f = GapFinder(max_effects=3, seed=s, config=GapConfig()).fit(case.scene, case.episodes)
print(s, truth, kind, "verdict", f.verdict_, [e["name"] for e in f.effects_], [d["effect"] for d in f.checked_.dropped],
      f"{time.time() - t0:.0f} s", flush=True)
