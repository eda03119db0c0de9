"""Recorded against simulated poses along one window of 4497026 episode 7, restarted at k0 = 16 from the noise-free
recording's state (development only; PYTHONPATH=<clone> python restart_series.py)."""
import sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.shooting import Shooter, Window
s,e,k0=4497026,7,16
clean = make_case(np.random.default_rng(s), "none", 0.0, 12, 3.0, noise_kind="white")
ep = clean.episodes[e]
sh = Shooter(clean.scene, clean.episodes, 1e-3, 2)
pred = sh.simulate(Window(e, k0, k0 + 100), None, None)
rec = ep.pose[k0:k0 + 101]
for i in range(0, 101, 4):
    print(f"t {ep.t[k0 + i]:.2f} ball rec {np.round(rec[i,0],3).tolist()} sim {np.round(pred[i,0],3).tolist()} | box rec {np.round(rec[i,1],4).tolist()} sim {np.round(pred[i,1],4).tolist()}")
print([ (b.name, b.shape, getattr(b,'size',None), b.radius, b.mass, b.friction) for b in clean.scene.bodies])
