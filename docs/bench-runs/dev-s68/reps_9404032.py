"""Development probe: 40 window-local replicates of the truth (linear_drag 0.2201) on 9404032's two test windows
(voe.gap.departure.local_replicates, the replicates deepened takes the median of), and ep 11's poses (development only)."""
import numpy as np

from voe.gap.bench import make_case
from voe.gap.departure import local_replicates
from voe.gap.effects import EFFECTS
from voe.gap.finder import ALL_EFFECTS
from voe.gap.shooting import make_windows
from voe.gap.stages import GapConfig, prepare

s=9404032
case = make_case(np.random.default_rng(s), "linear_drag", 1e-3, 12, 3.0, noise_kind="white")
cfg = GapConfig()
p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
wins = make_windows(p.episodes, list(p.split.test), cfg.locate_window, bad_start=p.bad)
eff = EFFECTS.get("linear_drag")(bodies=None)
par = np.array([0.2201])
for seed in (0, 1):
    r = local_replicates(p.shooter, wins, p.sigma, p.phi, np.random.default_rng(seed), 20, p.jitter, eff, par)
    print("truth replicates z per window (20 draws):")
    print(np.round(r.T, 1))
ep = p.episodes[11]
t = ep.t
w = wins[1]
print("ep 11 pose ball/box at window start and every 0.1 s:")
for k in range(w.k0, w.k1 + 1, 10):
    print(f"t={t[k]:.2f}", np.round(ep.pose[k], 3).tolist())
