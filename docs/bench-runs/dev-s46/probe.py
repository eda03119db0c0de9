"""The case loop the session-46 probes share (deepen_params.py, residual_departure.py): each wraps the finder's
carry-over bars (``voe.gap.carry_over.worse_on_test``) to log what they saw, then runs the finder on each
SEED:TRUTH:NOISE argument and prints one JSON line per case with that log. Diagnosis only."""
import json
import sys
import time
from collections.abc import Callable

import numpy as np

import voe.gap.carry_over as co
import voe.gap.finder as finder_mod
from voe.gap.bench import make_case
from voe.gap.finder import GapConfig, GapFinder


def run(wrapper: Callable, log: list, on_case: Callable = lambda case: None) -> None:
    """Put ``wrapper`` in place of ``worse_on_test`` (the finder imports it by name, so both places), then
    run every case of ``sys.argv[1:]``, ``log`` cleared and ``on_case(case)`` called before each."""
    co.worse_on_test = wrapper
    finder_mod.worse_on_test = wrapper
    for arg in sys.argv[1:]:
        seed, truth, nk = arg.split(":")
        t0 = time.time()
        log.clear()
        case = make_case(np.random.default_rng(int(seed)), truth, 1e-3, 12, 3.0, noise_kind=nk)
        on_case(case)
        f = GapFinder(max_effects=3, seed=int(seed), config=GapConfig()).fit(case.scene, case.episodes)
        print(json.dumps({"case": int(seed), "truth": truth, "nk": nk, "names": [e["name"] for e in f.effects_],
                          "verdict": f.verdict_, "asked": log, "sec": round(time.time() - t0)}), flush=True)
