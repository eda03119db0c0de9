"""CPU seconds of the departure's replicates on bench/gap_speed.py's case (20 episodes x 5 s): main's
(episode replicates, half-second windows) against window-local ones on the 1-s windows."""
import time, numpy as np
from voe.gap.bench import make_case
from voe.gap.stages import GapConfig, prepare
from voe.gap.finder import GapFinder
from voe.gap import departure as D
from voe.gap.locate import window_z
from voe.gap.shooting import make_windows
from voe.gap.synth import null_like
from dump_local import local_replicates
case = make_case(np.random.default_rng(3), 'quadratic_drag', episodes=20, duration=5.0)
p = prepare(case.scene, case.episodes, GapFinder(seed=0).effects, GapConfig())
rng = np.random.default_rng(0)
w1 = make_windows(p.episodes, list(range(len(p.episodes))), 1.0, bad_start=p.bad)
w05 = make_windows(p.episodes, list(range(len(p.episodes))), 0.5, bad_start=p.bad)
null_eps = null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi)
t = time.process_time()
from voe.gap.shooting import Shooter
window_z(p.shooter, w05, p.sigma); window_z(Shooter(p.scene, null_eps, p.substep, p.half), w05, p.sigma)
D.more_replicates(p.scene, p.episodes, p.sigma, p.phi, p.substep, p.half, w05, rng)
a = time.process_time() - t
for R in (10, 20):
    t = time.process_time(); local_replicates(p.shooter, w1, p.sigma, p.phi, rng, R); b = time.process_time() - t
    print(f"windows {len(w1)} (1 s), {len(w05)} (0.5 s); main's half-second part {a:.2f} cpu-s; window-local R={R} {b:.2f} cpu-s")
