"""Window start states next to impacts: fitted on one side only; near contact from outlines."""

import numpy as np

from voe.gap.context import near_contact, surface_gap
from voe.gap.recordings import Episode
from voe.gap.shooting import local_state, one_sided_factor, start_sides
from voe.sim.scenefile import BodySpec, SceneSpec


def test_start_sides_centred_where_clean_one_sided_next_to_an_impact():
    impact = np.zeros(200, bool)
    impact[100:105] = True
    side = start_sides(impact, 8)  # span 17 samples, one of margin
    assert side[50] == 0 and side[150] == 0  # far from the impact: centred
    assert np.all(side[100:105] == 2)  # never on the impact itself
    assert side[105] == 2 and side[99] == 2  # one sample of margin
    assert side[106] == 1 and side[113] == 1  # just after: fitted forward, on the clean side
    assert side[98] == -1 and side[91] == -1  # just before: fitted backward
    assert side[114] == 0 and side[90] == 0  # the centred span (8 + 1 each side) is clear again
    short = np.zeros(60, bool)
    short[[20, 35]] = True  # two bounces 15 samples apart: no clean span of 17 between them
    assert np.all(start_sides(short, 8)[21:35] == 2)
    np.testing.assert_array_equal(start_sides(np.zeros(50, bool), 5), 0)


def test_one_sided_state_ignores_the_far_side_of_a_bounce():
    t = np.arange(101) / 100
    y = np.where(t < 0.5, 1.0 - 2.0 * (t - 0.5), 1.0 + 3.0 * (t - 0.5))  # a kink at 0.5 s: -2 then +3 m/s
    pose = np.zeros((101, 1, 3))
    pose[:, 0, 1] = y
    ep = Episode(0, t, pose)
    _, v_fwd, sxx_fwd = local_state(ep, 51, 8, side=1)
    _, v_back, _ = local_state(ep, 49, 8, side=-1)
    _, v_c, sxx_c = local_state(ep, 51, 8)
    assert abs(v_fwd[0, 1] - 3.0) < 1e-6 and abs(v_back[0, 1] + 2.0) < 1e-6
    assert abs(v_c[0, 1] - 3.0) > 0.3  # the centred fit straddles the kink
    assert abs(sxx_c / sxx_fwd - one_sided_factor(17)) < 1e-9 and 2.0 < one_sided_factor(17) < 3.0


def test_near_contact_uses_the_outlines_not_bounding_circles():
    scene = SceneSpec((0.0, -9.81), (BodySpec("ball", "circle", mass=1.0, radius=0.1),
                                     BodySpec("box", "box", mass=1.0, size=(0.3, 0.2))), (), ())
    pose = np.zeros((3, 2, 3))
    pose[:, 1] = [0.0, 0.1, 0.0]  # box centre
    pose[0, 0] = [0.0, 0.36, 0.0]  # 6 cm above the box top: the bounding circles (0.18 + 0.1) overlap
    pose[1, 0] = [0.255, 0.1, 0.0]  # 5 mm beside its side
    pose[2, 0] = [0.0, 0.1 + 0.1 + 0.1 - 0.002, 0.0]  # resting on top, 2 mm overlap
    gap = surface_gap(scene, 0, 1, pose[:, 0], pose[:, 1])
    np.testing.assert_allclose(gap, [0.06, 0.005, -0.002], atol=1e-9)
    ep = Episode(0, np.arange(3) / 100, pose)
    np.testing.assert_array_equal(near_contact(scene, ep), [False, True, True])
