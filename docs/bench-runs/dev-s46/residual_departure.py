"""Dev probe (PYTHONPATH=<checkout>, diagnosis only): does what the final model leaves on the test split depart
from the model's own window-local replicates? Session 46's question (b) from the gust misnames 1066143 and 1066149.

For each case: run the finder; wherever the carry-over bars are asked (each look's final model), take the test
windows' z with the model (the data's, ``Verification.z_after``) and ``REPLICATES`` window-local replicates of the
model itself at each window's parameters (``voe.gap.departure.local_replicates`` with the model, as
``voe.gap.carry_over.deepened`` draws them, but for every test window), and print the departure test's tail p of
the data against them (``voe.gap.departure.tail_p``: how far data windows exceed their own replicates, (R + 1)^-k
for k departing windows) with the per-window numbers. A right name should leave windows its replicates reach; a
library law fitted to physics outside the library should not. Usage: ... residual_departure.py SEED:TRUTH:NOISE ..."""

import numpy as np
from probe import run

import voe.gap.carry_over as co
from voe.gap.check import heldout_pairs
from voe.gap.departure import REPLICATES, local_replicates, tail_p

LOG = []
_orig = co.worse_on_test


def model_replicates(c, p, config, seed):
    """The test windows' z with ``c.model`` (W,) and ``REPLICATES`` window-local replicates of the model at each
    window's parameters (R, W), drawn with ``seed`` as ``voe.gap.carry_over.deepened`` draws them."""
    pairs = heldout_pairs(p, c.model, config)[0]
    za = np.asarray(c.verification.z_after)  # (W,)
    rng = np.random.default_rng(seed)
    local = np.column_stack([local_replicates(p.shooter, [w], p.sigma, p.phi, rng, REPLICATES, p.jitter, c.model.effect,
                                              np.asarray(params, dtype=float))[:, 0] for w, params in pairs])  # (R, W)
    return za, local


def worse_on_test(c, p, config, z_thr, null_episodes=None, seed=0):
    out = _orig(c, p, config, z_thr, null_episodes, seed)
    if c.model is None:
        return out
    za, local = model_replicates(c, p, config, seed)
    LOG.append({"keys": list(c.keys), "kept": out.model is not None, "z_thr": round(z_thr, 2),
                "p_tail": round(tail_p(za, local), 5), "z_after": [round(float(x), 1) for x in za],
                "rep_median": [round(float(x), 1) for x in np.median(local, axis=0)],
                "rep_max": [round(float(x), 1) for x in local.max(axis=0)]})
    return out


if __name__ == "__main__":
    run(worse_on_test, LOG)
