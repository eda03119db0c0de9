"""How well the nominal simulator, restarted from the noise-free recording's state, follows that recording,
window by window along one episode (development only).

    PYTHONPATH=<clone> python restart.py SEED TRUTH NOISE_KIND EPISODE
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.context import frame_labels
from voe.gap.shooting import Shooter, Window

s, truth, kind, e = int(sys.argv[1]), sys.argv[2], sys.argv[3], int(sys.argv[4])
clean = make_case(np.random.default_rng(s), truth, 0.0, 12, 3.0, noise_kind=kind)
ep = clean.episodes[e]
sh = Shooter(clean.scene, clean.episodes, 1e-3, 2)
lab = frame_labels(clean.scene, ep)
for k0 in (2, 5, 8, 12, 16, 20, 30, 40, 60, 80, 120, 160):
    k1 = min(k0 + 100, len(ep.t) - 1)
    r = sh.residual(Window(e, k0, k1), None, None)
    print(f"  k0 {k0:3d} t {ep.t[k0]:.2f} labels {lab[k0].tolist()}: RMS ball {1e3 * np.sqrt((r[:, 0] ** 2).mean()):7.2f} mm, "
          f"box {1e3 * np.sqrt((r[:, 1] ** 2).mean()):7.2f} mm; box v {np.round(sh.initial(e, k0)[1][1], 3).tolist()}")
