"""Dev probe (PYTHONPATH=<checkout>, diagnosis only): for each case, run the finder and, wherever the carry-over bar
``deepened`` is asked, log each test window's z without/with the model, the clean replicate's z and the model's own
replicates' median z (as main), and the median z of replicates whose motion is drawn at parameters spread over the
model's 95 % interval (normal, sd = interval width / 3.92, clipped to the interval) while their z is taken against the
fitted model, as the data's is: a posterior-predictive spread that includes the parameter's uncertainty.
Question (session 46 lead, 1066071): does a right name's deepened window fall inside that spread while the misnames
the bar catches (4593142, 1967147, 1078143, 6219142) stay outside it? Usage: ... deepen_params.py SEED:TRUTH:NOISE ..."""

import numpy as np
from probe import run

import voe.gap.carry_over as co
from voe.gap.check import heldout_pairs
from voe.gap.departure import ORDER
from voe.gap.locate import window_z
from voe.gap.recordings import Episode
from voe.gap.shooting import Shooter, Window
from voe.gap.synth import replicate_noise

LOG = []
TRUTH = {}  # the case's truth parameters by effect name (single-effect cases: the window's z at the truth too)


def drawn_replicates(shooter, w, sigma, phi, rng, n, jitter, effect, fitted, lo, hi):
    """(n,) window z of replicates generated at parameters drawn over [lo, hi], measured against ``fitted``."""
    n_fit = max(2 * shooter.half + 1, ORDER + 3)
    ep = shooter.episodes[w.ep]
    a = max(0, min(w.k0 - n_fit // 2, len(ep.t) - n_fit, w.k0))
    seg = Episode(ep.id, ep.t[a:w.k1 + 1].copy(), ep.pose[a:w.k1 + 1])
    win, whole = Window(0, w.k0 - a, w.k1 - a), Window(0, 0, len(seg.t) - 1)
    base = Shooter(shooter.scene, [seg], shooter.substep, shooter.half).simulate_many([whole], effect, fitted)[0]
    sd = (hi - lo) / 3.92
    out = []
    for _ in range(n):
        p = np.clip(fitted + sd * rng.standard_normal(fitted.shape), lo, hi)
        drawn = Shooter(shooter.scene, [Episode(seg.id, seg.t, base + replicate_noise(base, seg.t, sigma, phi, jitter, rng))],
                        shooter.substep, shooter.half)
        path = drawn.simulate_many([whole], effect, p)[0]  # the truth's motion at the drawn parameters
        rep = Shooter(shooter.scene, [Episode(seg.id, seg.t, path + replicate_noise(path, seg.t, sigma, phi, jitter, rng))],
                      shooter.substep, shooter.half)
        res = rep.residuals([win], effect, fitted)  # against the fitted model, as the data's window
        out.append(float(window_z(rep, [win], sigma, res).max()))
    return np.array(out)


_orig = co.worse_on_test


def worse_on_test(c, p, config, z_thr, null_episodes=None, seed=0):
    out = _orig(c, p, config, z_thr, null_episodes, seed)
    if c.model is None or null_episodes is None:
        return out
    v = c.verification
    pairs = heldout_pairs(p, c.model, config)[0]
    zb, za = np.asarray(v.z_before), np.asarray(v.z_after)
    null = Shooter(p.scene, null_episodes, p.substep, p.half)
    zn = window_z(null, [w for w, _ in pairs], p.sigma).max(axis=(1, 2))
    rise = np.sqrt(np.maximum(0.0, za ** 2 - zb ** 2))
    rng = np.random.default_rng(seed)
    rows = []
    for i in np.argsort(-rise)[:3]:  # the three largest rises
        w, params = pairs[i]
        params = np.asarray(params, dtype=float)
        lo, hi = np.minimum(c.lower, params), np.maximum(c.upper, params)
        zm = co.local_replicates(p.shooter, [w], p.sigma, p.phi, rng, config.deepen_replicates, p.jitter,
                                 c.model.effect, params)
        zd = drawn_replicates(p.shooter, w, p.sigma, p.phi, rng, config.deepen_replicates, p.jitter, c.model.effect,
                              params, lo, hi)
        zt = None
        if len(c.keys) == 1 and c.keys[0] in TRUTH:  # the data's window against the truth itself
            res = p.shooter.residuals([w], c.model.effect, TRUTH[c.keys[0]])
            zt = round(float(window_z(p.shooter, [w], p.sigma, res).max()), 2)
        rows.append({"zb": round(float(zb[i]), 2), "za": round(float(za[i]), 2), "z_truth": zt,
                     "rise": round(float(rise[i]), 2),
                     "thr": round(z_thr, 2), "zn": round(float(zn[i]), 2), "zm_med": round(float(np.median(zm)), 2),
                     "zd_med": round(float(np.median(zd)), 2), "zd": [round(float(x), 1) for x in np.sort(zd)]})
    LOG.append({"keys": list(c.keys), "params": np.round(c.model.params, 4).tolist(),
                "lower": np.round(c.lower, 4).tolist(), "upper": np.round(c.upper, 4).tolist(),
                "kept": out.model is not None, "windows": rows})
    return out


def _truth(case):
    TRUTH.clear()
    TRUTH.update({k: np.asarray(v[0], dtype=float) for k, v in case.true.items()})


run(worse_on_test, LOG, _truth)
