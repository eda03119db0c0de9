import numpy as np

from voe.sim.render import Renderer
from voe.sim.rollout import simulate
from voe.sim.scene import FEATURE_NAMES, Body, Occluder, Scene, Segment, SimConfig
from voe.sim.world import World

FLOOR = Segment((-20, 0.5), (30, 0.5), 0.1)


def ball(**kw):
    base = dict(slot=0, shape="circle", width=1.0, height=1.0, x=1.0, y=1.1)
    base.update(kw)
    return Body(**base)


def test_free_fall_matches_kinematics():
    cfg = SimConfig(n_frames=11)
    rec = simulate(Scene(bodies=(ball(y=8.0),)), cfg)
    y = rec.states[:, 0, FEATURE_NAMES.index("y")]
    t = np.arange(11) * cfg.dt
    np.testing.assert_allclose(y, 8.0 - 0.5 * 9.81 * t**2, atol=0.02)


def test_sliding_on_frictionless_floor_keeps_speed():
    rec = simulate(Scene(bodies=(ball(vx=2.0),), statics=(FLOOR,)), SimConfig(n_frames=20))
    vx = rec.states[:, 0, FEATURE_NAMES.index("vx")]
    np.testing.assert_allclose(vx, 2.0, atol=1e-4)


def test_occluder_hides_object_and_state_is_nan():
    occ = Occluder(3.0, 0.0, 6.0, 3.0)
    rec = simulate(Scene(bodies=(ball(x=4.5),), statics=(FLOOR,), occluders=(occ,)), SimConfig(n_frames=3))
    assert not rec.present[:, 0].any() and rec.exists[:, 0].all()
    assert np.isnan(rec.states[:, 0]).all()


def test_copy_branches_keep_identical_futures():
    w = World(Scene(bodies=(ball(vx=1.5, y=3.0),), statics=(FLOOR,)), 0.05, 10)
    for _ in range(5):
        w.step()
    a, b = w.copy(), w.copy()
    for _ in range(10):
        a.step()
        b.step()
    np.testing.assert_array_equal(a.observe(2), b.observe(2))
    b.remove(0)
    assert 0 not in b.bodies() and 0 in a.bodies()


def test_passable_object_falls_through_floor_only_when_asked():
    wall = Segment((3.0, 0.5), (3.0, 4.0), 0.1, kind="wall")
    scene = Scene(bodies=(ball(y=2.0, vx=4.0),), statics=(FLOOR, wall))
    cfg = SimConfig(n_frames=20)
    ghost = simulate(scene, cfg, {1: lambda w: w.set_passable(0, statics=True, objects=False)})
    x, y = ghost.states[-1, 0, 0], ghost.states[-1, 0, 1]
    assert x > 3.5 and abs(y - 1.1) < 0.05  # through the wall, still on the floor
    solid = simulate(scene, cfg)
    assert solid.states[-1, 0, 0] < 3.0  # bounced off the wall
    sinker = simulate(scene, cfg, {1: lambda w: w.set_passable(0, statics=True, floor=True)})
    assert not sinker.present[-1, 0] or sinker.states[-1, 0, 1] < 0.0


def test_subpixel_motion_changes_pixels():
    r = Renderer([], [], (10.0, 10.0), 64)
    spec = ball()
    f1 = r.frame([(spec, 5.0, 5.0, 0.0)])
    f2 = r.frame([(spec, 5.03, 5.0, 0.0)])  # a fifth of a pixel
    assert (f1 != f2).sum() > 0
    assert f1.dtype == np.uint8 and f1.shape == (64, 64)


def test_occluder_drawn_in_front():
    occ = Occluder(4.0, 4.0, 6.0, 6.0)
    r = Renderer([], [occ], (10.0, 10.0), 64)
    with_obj = r.frame([(ball(), 5.0, 5.0, 0.0)])
    without = r.frame([])
    assert np.array_equal(with_obj, without)


def test_hidden_means_pixel_identical_to_empty_scene():
    """An object flagged not-present behind a screen must not tint a single pixel."""
    occ = Occluder(3.0, 0.0, 6.0, 3.0)
    floor = (FLOOR,)
    cfg = SimConfig(n_frames=40)
    with_obj = simulate(Scene(bodies=(ball(x=0.5, vx=3.0),), statics=floor, occluders=(occ,)), cfg)
    empty = simulate(Scene(bodies=(), statics=floor, occluders=(occ,)), cfg)
    hidden = np.flatnonzero(with_obj.exists[:, 0] & ~with_obj.present[:, 0])
    assert hidden.size >= 3
    for t in hidden:
        assert np.array_equal(with_obj.frames[t], empty.frames[t])
