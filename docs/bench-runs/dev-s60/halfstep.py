"""A ball in free flight simulated by pymunk at 1 ms substeps, sampled at 100 Hz with no noise: the start velocity the
shooter estimates from positions against the continuous value, and the drift of a restart (development only;
PYTHONPATH=<clone> python halfstep.py)."""
import numpy as np
from voe.gap.shooting import Shooter, Window, local_state
from voe.gap.synth import simulate_episode
from voe.sim.scenefile import BodySpec, SceneSpec, StaticSpec
r = 0.1
scene = SceneSpec((0.0, -9.81), (BodySpec("ball", "circle", mass=1.0, radius=r, friction=0.6, elasticity=0.5),),
                  (StaticSpec((-50.0, -100.0), (50.0, -100.0), 0.0, 1.0, 1.0),), ())
t = np.arange(201) / 100.0
ep = simulate_episode(scene, 0, t, np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, 5.0, 0.0]]), None, None, np.zeros((1, 3)), np.random.default_rng(0))
for half in (2, 5, 12):
    sh = Shooter(scene, [ep], 1e-3, half)
    k0 = 50
    pose, vel, _ = sh.initial(0, k0)
    true_v = 5.0 - 9.81 * t[k0]
    r_ = sh.residual(Window(0, k0, k0 + 100), None, None)
    print(f"half {half}: est vy {vel[0,1]:.5f} vs continuous {true_v:.5f} (diff {1e3*(vel[0,1]-true_v):+.2f} mm/s); y error after 0.5 s {1e3*r_[50,0,1]:+.2f} mm, after 1 s {1e3*r_[100,0,1]:+.2f} mm")
