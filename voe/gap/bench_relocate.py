"""Rescore a stored bench case with this code's location stage (``bench/gap_relocate.py``).

Why exact: a change to the departure test reaches only the verdict of a case that named nothing
(``unexplained`` when located and the departure p is below ``voe.gap.departure.ALPHA`` or a
stretch's z is infinite, else ``consistent``); the departure p is read nowhere else, the finder's
random stream is not used after the location, and the located stretches and the clean replicate
are drawn before the departure test's replicates. So rerunning the location as the finder runs it
(same case, seed and config) gives the verdict this code would give, provided the rest of the
location is unchanged, which ``relocate`` checks (the count of stretches above the clean
replicate's bar, no timing jitter modelled) and refuses otherwise. Stretches located against
their windows' own replicates (``voe.gap.stages.locate_parts``) come after the departure test and
do not steer the search, so a store made before them rescores exactly too. What it cannot check:
the cases that named an effect are not rerun, so the rescore is the current code's figure only when the code changed since the stored run in the
departure test alone (``bench/gap_relocate.py`` prints which sources made the stored run).
"""

from __future__ import annotations

import numpy as np

from voe.errors import DataError
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder, unnamed_verdict
from voe.gap.locate import LOCAL, by_bar
from voe.gap.stages import GapConfig, locate_step, prepare


def relocate(r: dict, run: dict) -> dict:
    """The stored case ``r`` with this code's departure p and verdict (``relocated``: the new p)."""
    config = GapConfig(cross_fit=bool(run.get("cross_fit", False)))
    case = make_case(np.random.default_rng(r["seed"]), r["truth"], run["noise"], run["episodes"], run["duration"],
                     noise_kind=r["noise_kind"])
    p = prepare(case.scene, case.episodes, GapFinder(seed=r["seed"]).effects, config)
    loc = locate_step(p, config, np.random.default_rng(r["seed"]))
    n_local = len(by_bar(loc.located, LOCAL))
    n_clean, stored = len(loc.located) - n_local, r["located"] - r.get("located_local", 0)
    if n_clean != stored or p.jitter is not None:
        raise DataError(f"case {r['seed']}: the location differs from the stored run (located {n_clean} "
                        f"vs {stored}, timing jitter modelled: {p.jitter is not None}); a rescore would not be exact")
    return {**r, "verdict": unnamed_verdict(loc.located, loc.departure_p), "located": len(loc.located),
            "located_local": n_local, "relocated": float(loc.departure_p)}
