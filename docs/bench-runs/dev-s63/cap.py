"""Print every ``deepened`` question of the whole finder on one bench case with the model's parameters (development
only; the parameters of tests/gap/test_carry_over.py's 1078143 case come from cap_1078143.txt).

    PYTHONPATH=<clone> python cap.py SEED TRUTH NOISE_KIND
"""
import sys

import numpy as np

import voe.gap.carry_over as co
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig

orig = co.deepened
def spy(p, model, config, z_thr, null_episodes, ver=None, seed=0):
    out = orig(p, model, config, z_thr, null_episodes, ver, seed)
    print("deepened", [q.name for q in model.effect.parts], [getattr(q, "bodies", None) for q in model.effect.parts],
          "params", model.params.tolist(), "fold_params", [np.asarray(f).tolist() for f in model.fold_params],
          "z_thr", z_thr, "seed", seed, "out", out, flush=True)
    return out
co.deepened = spy
s, truth, kind = int(sys.argv[1]), sys.argv[2], sys.argv[3]
case = make_case(np.random.default_rng(s), truth, 1e-3, 12, 3.0, noise_kind=kind)
f = GapFinder(max_effects=3, seed=s, config=GapConfig()).fit(case.scene, case.episodes)
print("verdict", f.verdict_)
