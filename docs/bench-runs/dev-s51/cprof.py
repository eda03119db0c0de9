import cProfile, pstats, sys
import numpy as np
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig
case = make_case(np.random.default_rng(3), "quadratic_drag", episodes=20, duration=5.0)
pr = cProfile.Profile()
pr.enable()
f = GapFinder(seed=0, n_jobs=1, config=GapConfig()).fit(case.scene, case.episodes)
pr.disable()
print("reused", f.problem_.shooter.bare.n_reused if hasattr(f.problem_.shooter, "bare") else None)
st = pstats.Stats(pr); st.sort_stats("tottime").print_stats(35)
