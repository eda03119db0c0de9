"""The departure test's parts on a bench case (development only): the windows with the largest data z, beside
the clean replicate's and the window-local replicates' z; the signed-rank and tail p-values.

    PYTHONPATH=<clone> python depart.py SEED TRUTH NOISE_KIND
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.departure import _signed_rank_p, local_replicates, tail_p
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.shooting import Shooter, make_windows
from voe.gap.stages import GapConfig, prepare
from voe.gap.synth import null_like

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
config = GapConfig()
p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
rng = np.random.default_rng(s)
windows = make_windows(p.episodes, list(range(len(p.episodes))), config.locate_window, bad_start=p.bad)
null_eps = null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi, p.jitter)
z_null = window_z(Shooter(p.scene, null_eps, p.substep, p.half), windows, p.sigma).max(axis=(1, 2))  # (W,)
z = window_z(p.shooter, windows, p.sigma).max(axis=(1, 2))
local = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, jitter=p.jitter)  # (R, W)
print(s, truth, kind, "half", p.half, "windows", len(windows), "signed-rank p", round(_signed_rank_p(z, z_null), 4),
      "tail p", round(tail_p(z, local), 4))
for i in np.argsort(-z)[:8]:
    w = windows[i]
    print(f"  ep {w.ep} t {p.episodes[w.ep].t[w.k0]:.2f}: data z {z[i]:.1f}, clean replicate {z_null[i]:.1f}, "
          f"local {np.round(np.sort(local[:, i]), 1).tolist()}")
