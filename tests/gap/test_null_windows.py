"""The null's windows are cut by the clean replicate's own contacts, not by the data's.

Why: the replicate starts from each episode's first state and follows the nominal physics, so
with a strong effect in the data its impacts fall elsewhere. Cut by the data's contacts, its
windows started inside its own impacts (7 of 15 selection windows on development case 1531056),
where the start velocity is estimated across the bounce and any candidate that damps the
garbage motion "gains": the threshold rose above the true second effect's gain.
"""

from __future__ import annotations

import numpy as np

import voe.gap.stages as stages
from voe.gap.bench import make_case
from voe.gap.greedy import SearchResult
from voe.gap.recordings import Episode
from voe.gap.stages import GapConfig, Location, _bad_starts, prepare


def test_null_windows_never_start_inside_the_replicates_own_contacts(monkeypatch):
    case = make_case(np.random.default_rng(1), "none", 1e-3, 6, 2.0)
    config = GapConfig()
    p = prepare(case.scene, case.episodes, ("linear_drag",), config)
    # a replicate whose contacts fall elsewhere: episode i replays episode n-1-i
    n = len(case.episodes)
    null_eps = [Episode(e.id, e.t, case.episodes[n - 1 - i].pose) for i, e in enumerate(case.episodes)]
    loc = Location([], [], 5.0, 5.0, null_eps)
    seen = {}

    def fake_greedy(data, candidates, null, *args, **kwargs):
        seen["data"], seen["null"] = data, null
        return SearchResult(None, (), ())

    monkeypatch.setattr(stages, "greedy", fake_greedy)
    stages.search_step(p, loc, config, 1, seed=0)
    null_bad, data_bad = _bad_starts(p.scene, null_eps, p.half), p.bad
    assert any((null_bad[i] != data_bad[i]).any() for i in range(n))  # the test means something
    for name, bad in (("null", null_bad), ("data", data_bad)):
        folds = seen[name].fitter.folds if name == "null" else seen[name].folds
        wins = [w for f in folds for w in list(f.train) + list(f.test) + list(f.pool or [])]
        assert wins and not any(bad[w.ep][w.k0] for w in wins), name
