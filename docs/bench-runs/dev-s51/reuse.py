import numpy as np, collections
from voe.gap import bare
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig
stats = collections.Counter()
orig = bare.Bare.simulate
def sim(self, shooter, wins, effect, params, key):
    bp = bare.bare_params(effect, params, shooter.scene) if key is not None else None
    n0 = self.n_reused
    out = orig(self, shooter, wins, effect, params, key)
    if bp is not None:
        stats["region windows"] += len(wins); stats["reused"] += self.n_reused - n0
    return out
bare.Bare.simulate = sim
case = make_case(np.random.default_rng(3), "quadratic_drag", episodes=20, duration=5.0)
f = GapFinder(seed=0, n_jobs=1, config=GapConfig()).fit(case.scene, case.episodes)
b = f.problem_.shooter.bare
print(dict(stats), "memo", len(b.memo), "contacts per window", np.mean([len(c) for _, c in b.memo.values()]), "max", max(len(c) for _, c in b.memo.values()))
