"""Attribute the speed bench's rollouts and their time to the finder's stages (one process, --jobs 1).

    python stageprof.py DEPTH [LO] [--effects]   (--effects: key by the effect's parts too)
"""
import sys, time, collections, traceback
BY_EFFECT = '--effects' in sys.argv
sys.argv = [a for a in sys.argv if a != '--effects']
import numpy as np
from voe.gap import shooting
from voe.gap.bench import make_case
from voe.gap.finder import GapFinder
from voe.gap.stages import GapConfig

depth = int(sys.argv[1]) if len(sys.argv) > 1 else 3
stats = collections.defaultdict(lambda: [0, 0.0, 0])
orig = shooting.Shooter.simulate_many
def wrapped(self, wins, effect, params):
    st = traceback.extract_stack()[:-1]
    chain = [f"{f.filename.split('/voe/')[-1].replace('.py','')}:{f.name}" for f in st if '/voe/' in f.filename]
    # drop everything up to finder fit
    try:
        i = max(k for k, c in enumerate(chain) if c.startswith('gap/finder:fit'))
        chain = chain[i + 1:]
    except ValueError:
        pass
    chain = [c for c in chain if not c.startswith(('gap/shooting', 'gap/parallel'))]
    lo = int(sys.argv[2]) if len(sys.argv) > 2 else 0; key = " > ".join(chain[lo:depth])
    if BY_EFFECT:
        key += " || " + ("none" if effect is None else "+".join(type(p).__name__ for p in effect.parts))
    t0 = time.process_time()
    out = orig(self, wins, effect, params)
    s = stats[key]; s[0] += len(wins); s[1] += time.process_time() - t0; s[2] += 1
    return out
shooting.Shooter.simulate_many = wrapped
case = make_case(np.random.default_rng(3), "quadratic_drag", episodes=20, duration=5.0)
t0 = time.process_time()
f = GapFinder(seed=0, n_jobs=1, config=GapConfig()).fit(case.scene, case.episodes)
tot = time.process_time() - t0
bare = getattr(f.problem_.shooter, "bare", None)  # voe.gap.bare (session 51)
if bare is not None:
    print("reused", bare.n_reused, "bare memo", len(bare.memo))
print("effects", [(e['name'], e['params']) for e in f.effects_], "rollouts", f.problem_.shooter.n_rollouts, "null", f.search_.null_rollouts)
print(f"total cpu {tot:.1f} s; in simulate_many {sum(s[1] for s in stats.values()):.1f} s")
for k, (n, t, c) in sorted(stats.items(), key=lambda kv: -kv[1][1]):
    print(f"{n:6d} win {c:5d} calls {t:6.1f} s  {k}")
