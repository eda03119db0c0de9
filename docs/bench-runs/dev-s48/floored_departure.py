"""Dev probe (PYTHONPATH=<checkout>, diagnosis only): session 46's residual-departure probe with a second p, the
departure test's tail p with every z (data and replicates alike) floored at the located threshold, so that only
excess above the threshold counts (as ``voe.gap.carry_over.deepened`` counts it). The lead of session 48: the
unfloored p dropped the real pendulum's right law (its recording departs from every library model by far more than
its noise, located threshold z = 200.7). The floor is the same for every row of a column, so the columns stay
exchangeable and the randomisation stays exact.

Usage: ... floored_departure.py SEED:TRUTH:NOISE ... | real   (``real``: the vendored real pendulum, as
``tests/gap/test_real_pendulum.py`` calls the finder)."""
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "dev-s46"))
from residual_departure import model_replicates  # noqa: E402 (session 46's probe, its replicate draws)

import voe.gap.carry_over as co  # noqa: E402
import voe.gap.finder as finder_mod  # noqa: E402
from voe.gap.bench import make_case  # noqa: E402
from voe.gap.departure import tail_p  # noqa: E402
from voe.gap.finder import GapConfig, GapFinder  # noqa: E402

REAL = Path(__file__).resolve().parents[3] / "data" / "real" / "single-pendulum"
NEAR = ("angular_damping", "linear_drag", "joint_friction", "spring_anchor", "constant_acceleration")
LOG = []
_orig = co.worse_on_test


def worse_on_test(c, p, config, z_thr, null_episodes=None, seed=0):
    out = _orig(c, p, config, z_thr, null_episodes, seed)
    if c.model is None:
        return out
    za, local = model_replicates(c, p, config, seed)  # (W,), (R, W)
    LOG.append({"keys": list(c.keys), "kept": out.model is not None, "z_thr": round(z_thr, 2),
                "p_tail": round(tail_p(za, local), 5),
                "p_floored": round(tail_p(np.maximum(za, z_thr), np.maximum(local, z_thr)), 5),
                "z_after": [round(float(x), 1) for x in za],
                "rep_max": [round(float(x), 1) for x in local.max(axis=0)]})
    return out


if __name__ == "__main__":
    co.worse_on_test = worse_on_test
    finder_mod.worse_on_test = worse_on_test
    for arg in sys.argv[1:]:
        t0 = time.time()
        LOG.clear()
        if arg == "real":
            f = GapFinder(effects=NEAR, seed=0).fit(REAL / "scene.json", REAL / "recordings.csv")
            row = {"case": "real pendulum", "truth": "angular_damping"}
        else:
            seed, truth, nk = arg.split(":")
            case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
            f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
            row = {"case": int(seed), "truth": truth, "nk": nk}
        print(json.dumps({**row, "names": [e["name"] for e in f.effects_], "verdict": f.verdict_, "asked": LOG,
                          "sec": round(time.time() - t0)}), flush=True)
