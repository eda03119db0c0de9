"""A restart's start velocity: the simulator's own, not the one read off its positions."""
import numpy as np

from voe.gap.shooting import Shooter, Window, local_state
from voe.gap.synth import simulate_episode
from voe.sim.scenefile import BodySpec, SceneSpec, StaticSpec

SUBSTEP = 1e-3


def _flight():
    """A ball in free flight for 2 s, pymunk at 1 ms, sampled at 100 Hz with no noise."""
    scene = SceneSpec((0.0, -9.81), (BodySpec("ball", "circle", mass=1.0, radius=0.1, friction=0.6, elasticity=0.5),),
                      (StaticSpec((-50.0, -100.0), (50.0, -100.0), 0.0, 1.0, 1.0),), ())
    t = np.arange(201) / 100.0  # (T,)
    ep = simulate_episode(scene, 0, t, np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, 5.0, 0.0]]), None, None,
                          np.zeros((1, 3)), np.random.default_rng(0))
    return scene, ep


def test_restarted_flight_follows_the_recording():
    """Restarted at 0.5 s, the simulator follows the noise-free recording for 1 s to a tenth of a
    millimetre; from the velocity read off positions (no half step) it drifts by g dt / 2 per
    second, 4.9 mm, which a knife-edge impact turns into a different bounce."""
    scene, ep = _flight()
    for half in (2, 5, 12):
        res = Shooter(scene, [ep], SUBSTEP, half).residual(Window(0, 50, 150), None, None)  # (n, B, 3)
        assert np.max(np.abs(res)) < 1e-4, half
    _, vel_read, _ = local_state(ep, 50, 5)
    _, vel_sim, _ = local_state(ep, 50, 5, SUBSTEP)
    assert abs((vel_sim - vel_read)[0, 1] - (-9.81 * SUBSTEP / 2)) < 1e-6  # half a substep of gravity
    assert abs(vel_read[0, 1] - (5.0 - 9.81 * 0.5 + 9.81 * SUBSTEP / 2)) < 1e-5  # positions lag the update
