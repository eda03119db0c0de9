"""Diagnosis (development seeds only): a case's test windows' z under nominal, a fitted value and the
truth, and the clean replicate's z, to see whether `deepened` blames a right model for a window that
the truth itself cannot predict. Usage: deep.py SEED TRUTH NOISE [PARAM ...]"""
import sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder
from voe.gap.stages import prepare, locate_parts
from voe.gap.check import heldout_pairs
from voe.gap.locate import window_z
from voe.gap.shooting import Shooter
from voe.gap.fit import FitResult

seed, truth, nk = int(sys.argv[1]), sys.argv[2], sys.argv[3]
fitted = [float(x) for x in sys.argv[4:]]
case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=nk)
config = GapConfig()
f = GapFinder(max_effects=3, seed=seed, config=config)
p = prepare(case.scene, case.episodes, f.effects, config)
print("true", case.true, "candidates", list(p.candidates)[:20])
eff = p.candidates[truth]
tp = np.asarray(case.true[truth][0], float)
pairs, note = heldout_pairs(p, None, config)
wins = [w for w, _ in pairs]
print(note, len(wins), "windows")
rng = np.random.default_rng(seed)
null_eps, finish = locate_parts(p, config, rng)
loc = finish()
zthr = loc.z_threshold
null = Shooter(p.scene, null_eps, p.substep, p.half)
zn = window_z(null, wins, p.sigma).max(axis=(1, 2))
zb = window_z(p.shooter, wins, p.sigma).max(axis=(1, 2))
zt = window_z(p.shooter, wins, p.sigma, p.shooter.residuals(wins, eff, tp)).max(axis=(1, 2))
zf = window_z(p.shooter, wins, p.sigma, p.shooter.residuals(wins, eff, np.asarray(fitted))).max(axis=(1, 2)) if fitted else zt
print(f"z_thr {zthr:.2f}")
for i, w in enumerate(wins):
    rise = np.sqrt(max(0, zf[i] ** 2 - zb[i] ** 2))
    print(f" win {i} ep {w.ep} k {w.k0}-{w.k1}: nominal {zb[i]:.1f} fitted {zf[i]:.1f} truth {zt[i]:.1f} replicate {zn[i]:.1f} rise {rise:.1f} bar {2*max(zn[i], zthr):.1f}")

# a replicate under the model (fitted value): whole episodes simulated with the effect from each
# episode's estimated start, the data's noise model added; then the model's window z on it
from voe.gap.recordings import Episode
from voe.gap.shooting import Window
from voe.gap.synth import replicate_noise
par = np.asarray(fitted or tp, float)
for rep in range(3):
    r2 = np.random.default_rng(1000 + rep)
    meps = []
    for i, ep in enumerate(p.episodes):
        m = p.shooter.simulate(Window(i, 0, len(ep.t) - 1), eff, par)
        meps.append(Episode(ep.id, ep.t.copy(), m + replicate_noise(m, ep.t, p.sigma, p.phi, p.jitter, r2)))
    ms = Shooter(p.scene, meps, p.substep, p.half)
    zm = window_z(ms, wins, p.sigma, ms.residuals(wins, eff, par)).max(axis=(1, 2))
    zmn = window_z(ms, wins, p.sigma).max(axis=(1, 2))
    print(" model replicate", rep, "model z", np.round(zm, 1), "nominal z on it", np.round(zmn, 1))
