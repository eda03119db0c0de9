"""Dev check (session 48): the vendored real pendulum with the finder of ``PYTHONPATH`` (here branch
``model-departure`` with ``GapConfig.own_departure_alpha`` set to 0.005 by default), as
``tests/gap/test_real_pendulum.py`` calls it: the verdict, the names and what the checks dropped, and why."""
import json

from floored_departure import NEAR, REAL

from voe.gap import GapFinder

f = GapFinder(effects=NEAR, seed=0).fit(REAL / "scene.json", REAL / "recordings.csv")
print(json.dumps({"verdict": f.verdict_, "names": [e["name"] for e in f.effects_], "fit": f.fit_,
                  "dropped": f.checked_.dropped}, default=str), flush=True)
