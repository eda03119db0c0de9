"""Development probe: each test window's z (the location's statistic, largest over bodies and variables) under
the nominal model, the hidden truth at its true parameters and a given fitted model, on the finder's test
episodes with the check's 1-s windows (development only).

    PYTHONPATH=<clone> python testz.py SEED TRUTH NOISE_KIND NAME=P1,P2[+NAME=...]

Why: the check's ``deepened`` drops a model that raises a test window into a departure; this shows whether the
truth itself raises that window (a chaotic window the model's replicates do not reproduce) or only the fit does.
"""
import sys

import numpy as np

from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.finder import ALL_EFFECTS
from voe.gap.locate import window_z
from voe.gap.shooting import make_windows
from voe.gap.stages import GapConfig, prepare

s, truth, kind, fitted = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
cfg = GapConfig()
p = prepare(case.scene, case.episodes, ALL_EFFECTS, cfg)
wins = make_windows(p.episodes, list(p.split.test), cfg.locate_window, bad_start=p.bad)


def model(spec):
    parts, params = [], []
    for item in spec:
        name, vals = item
        parts.append(EFFECTS.get(name)(bodies=None))
        params.append(np.asarray(vals, dtype=float))
    return (parts[0] if len(parts) == 1 else EffectSum(tuple(parts))), np.concatenate(params)


def zs(effect=None, params=None):
    res = None if effect is None else p.shooter.residuals(wins, effect, params)
    return window_z(p.shooter, wins, p.sigma, res).max(axis=(1, 2))  # (W,)


rows = [("nominal", zs())]
rows.append(("truth", zs(*model([(k, v) for k, (v, _) in case.true.items()]))))
rows.append(("fitted", zs(*model([(x.split("=")[0], [float(v) for v in x.split("=")[1].split(",")])
                                  for x in fitted.split("+")]))))
print(s, truth, kind, "test episodes", p.split.test, "true", {k: np.round(v, 4).tolist() for k, (v, _) in case.true.items()})
print("window (episode, t0-t1 s):", " ".join(f"{w.ep}:{p.episodes[w.ep].t[w.k0]:.2f}-{p.episodes[w.ep].t[w.k1]:.2f}"
                                             for w in wins))
for name, z in rows:
    print(f"{name:8s}", " ".join(f"{v:7.1f}" for v in z), f"| median {np.median(z):.1f}")
