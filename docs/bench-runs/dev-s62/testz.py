"""Why a carry-over guard dropped a case's model (development only): each test window's z without the
model, with the fitted model, and with the truth's own parameters (the same windows, the same restarts).

    PYTHONPATH=<clone> python testz.py SEED TRUTH NOISE_KIND
"""
import sys

import numpy as np

import voe.gap.carry_over as co
import voe.gap.finder as fm
from voe.gap.bench import make_case
from voe.gap.check import heldout_pairs
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import EffectSum
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig
from voe.gap.verify import verify

s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
print("truth", truth, {k: (np.round(v[0], 4).tolist(), v[1]) for k, v in case.true.items()})
seen = []
orig = co.worse_on_test


def spy(c, p, config, z_thr, null_episodes=None, seed=0):
    out = orig(c, p, config, z_thr, null_episodes, seed)
    if c.model is not None:
        v = c.verification
        print("look:", p.split.scheme, "model", [e.name for e in c.model.effect.parts], np.round(c.model.params, 4).tolist(),
              "z_thr", round(z_thr, 2), "dropped" if out.model is None else "kept")
        print("  z nominal", np.round(v.z_before, 1).tolist())
        print("  z fitted ", np.round(v.z_after, 1).tolist())
        print("  median   ", round(v.median_z_before, 2), "->", round(v.median_z_after, 2))
        seen.append((c, p, config, z_thr))
    return out


fm.worse_on_test = spy
f = GapFinder(max_effects=3, seed=s, config=GapConfig()).fit(case.scene, case.episodes)
print("verdict", f.verdict_, [e["name"] for e in f.effects_], "first look", f.first_look_)
for d in f.checked_.dropped:
    print("  drop", d["effect"], "|", d["reason"][:400])
for c, p, config, z_thr in seen:  # the truth's parameters on the same test windows
    parts, params = [], []
    for name, (pv, bodies) in case.true.items():
        eff = EFFECTS.get(name.split("[")[0])
        e = eff(bodies) if bodies else eff()
        parts.append(e)
        params.append(np.asarray(pv, float))
    eff = EffectSum(tuple(parts))
    tp = np.concatenate(params)
    pairs, _ = heldout_pairs(p, c.model, config)
    v = verify(p.shooter, [(w, tp) for w, _ in pairs], eff, p.sigma, z_thr)
    print("look:", p.split.scheme, "truth params", tp.round(4).tolist())
    print("  z truth  ", np.round(v.z_after, 1).tolist(), "median", round(v.median_z_after, 2))
