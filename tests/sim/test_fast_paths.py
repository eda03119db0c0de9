"""The fast paths of generation give the same numbers as the plain ones they replace."""

from __future__ import annotations

import math

import numpy as np

from voe.sim.render import STATIC_INTENSITY, Renderer, _sd_segment
from voe.sim.rollout import Recorder, simulate
from voe.sim.scene import Body, Occluder, Scene, Segment, SimConfig
from voe.sim.world import World

FLOOR = Segment((-20, 0.5), (30, 0.5), 0.1)


def _by_properties(world: World, k: int) -> np.ndarray:
    """What ``World.poses`` reads, one pymunk property at a time (the plain path)."""
    out = np.full((k, 11), np.nan)
    for b in world.space.bodies:
        s = b.voe_spec
        angle = math.remainder(b.angle, 2 * math.pi) if s.shape == "box" else b.angle
        out[s.slot] = (b.position.x, b.position.y, angle, b.velocity.x, b.velocity.y,
                       b.angular_velocity, s.shape == "circle", s.shape == "box", s.width, s.height,
                       s.intensity)
    return out


def test_batched_pose_reads_equal_property_reads_even_when_bodies_change():
    bodies = (Body(2, "box", 1.0, 0.6, 2.0, 4.0, angle=7.0, vx=1.0, omega=3.0),
              Body(0, "circle", 0.8, 0.8, 6.0, 1.0, vx=-1.0))
    world = World(Scene(bodies=bodies, statics=(FLOOR,)), 0.05, 10)
    rec = Recorder(Scene(bodies=bodies, statics=(FLOOR,)), SimConfig(n_frames=12))
    plain = []
    for t in range(12):
        if t:
            world.step()
        if t == 4:
            world.remove(0)  # the new body may take the freed address (and id)
            world.add(Body(1, "circle", 0.5, 0.5, 8.0, 3.0, intensity=0.7))
        plain.append(_by_properties(world, 4))
        rec.capture(world)
        np.testing.assert_array_equal(world.poses(4), plain[-1])
    np.testing.assert_array_equal(rec.truth(), np.stack(plain).astype(np.float32))
    assert np.isnan(rec.truth()[4:, 0]).all() and not np.isnan(rec.truth()[4:, 1]).any()


def test_background_drawn_near_statics_only_equals_the_full_frame():
    segs = (FLOOR, Segment((3.0, 0.5), (4.0, 6.0), 0.2, kind="ramp"))
    r = Renderer(segs, (Occluder(2.0, 0.0, 5.0, 3.0),), (10.0, 10.0), 64)
    ys, xs = np.mgrid[0:64, 0:64].astype(np.float64)
    px, py = (xs + 0.5) * 10 / 64, 10 - (ys + 0.5) * 10 / 64
    back = np.zeros((64, 64))
    for s in segs:
        cov = np.clip(0.5 - _sd_segment(px, py, s.a, s.b, s.radius) / (10 / 64), 0, 1)
        back = back * (1 - cov) + STATIC_INTENSITY * cov
    np.testing.assert_array_equal(r._layers[0][..., 0], back.astype(np.float32))


def test_ghost_rollouts_are_never_drawn():
    scene = Scene(bodies=(Body(0, "circle", 1.0, 1.0, 2.0, 1.1, vx=1.0),), statics=(FLOOR,))
    rec = simulate(scene, SimConfig(n_frames=6))
    assert rec._frames is None  # nothing drawn yet
    frames = rec.frames
    assert frames.shape == (6, 64, 64) and rec.frames is frames
