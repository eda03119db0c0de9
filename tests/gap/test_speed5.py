"""Session 17's speed-ups (gapspeed5) give the same numbers as the code they replaced.

The reference is session 16's lockstep loop (one Python turn per substep, every world stepped
in it), kept here; the nominal replicates against ``simulate_episode`` one episode at a time. A
changed bit fails.
"""

from __future__ import annotations

import gc

import numpy as np
import pytest

from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.rollout import run_many, tiled
from voe.gap.shooting import local_state, noise_model
from voe.gap.synth import null_like, simulate_episode
from voe.sim import lockstep
from voe.sim.lockstep import _Kick, _kick_dts, _plan, _Reader, _rows, _segments
from voe.sim.scenefile import SimWorld


def _old_lockstep(worlds, times, substep, force=None, kick_every=4e-3):
    """``run_lockstep`` as it was before session 17: substep by substep, world by world."""
    nw = len(worlds)
    plans = [_plan(np.ascontiguousarray(t, dtype=float).tobytes(), float(substep)) for t in times]
    hs = [h for h, _, _ in plans]
    lengths = [len(h) for h in hs]
    rows = _rows(worlds)
    bufs = lockstep._buffers(nw + 1)
    poses = [_Reader(w.space, b, lockstep._POSE) for w, b in zip(worlds, bufs, strict=False)]
    for r in poses:
        r.reset()
        r.read()
    record: dict[int, list[int]] = {}
    for i, (_, ends, _) in enumerate(plans):
        for e in ends:
            record.setdefault(e - 1, []).append(i)
    order = sorted(range(nw), key=lambda i: -lengths[i])
    active = [(worlds[i].space._space, hs[i]) for i in order]
    ends_at = [lengths[i] for i in order]
    k_kick = max(1, round(kick_every / substep))
    kick = _Kick(worlds, force, bufs[nw], rows, _kick_dts([a for _, _, a in plans], lengths, k_kick)) \
        if force is not None else None
    for j in range(max(lengths)):
        while ends_at[-1] <= j:
            ends_at.pop()
            active.pop()
        if kick is not None and j % k_kick == 0:
            kick(j // k_kick)
        for space, h in active:
            lockstep.lib.cpSpaceStep(space, h[j])
        for i in record.get(j, ()):
            poses[i].read()
    nb = len(worlds[0].bodies)
    return [r.array(rows, 3)[:, :nb].copy() for r in poses]


@pytest.fixture(scope="module")
def case():
    return make_case(np.random.default_rng(2), "none", episodes=2, duration=2.0)


def _windows(case, rng, jitter):
    starts, times = [], []
    for e in case.episodes:
        for k0 in (3, 50, 111):
            starts.append(local_state(e, k0)[:2])
            t = e.t[k0:k0 + int(rng.integers(1, 70))]  # from a single sample to 0.7 s
            if jitter and len(t) > 1:
                t = t + np.concatenate([[0.0], rng.uniform(-4e-3, 4e-3, len(t) - 1)])
                t[1:] = np.maximum.accumulate(t[1:])  # some samples closer than half a substep
            times.append(t)
    return starts, times


@pytest.mark.parametrize("name", [None, "quadratic_drag", "friction_region", "restitution_region", "mass"])
@pytest.mark.parametrize("kick_every", [4e-3, 3e-3, 7e-3])
def test_segmented_loop_is_the_substep_loop_to_the_bit(case, name, kick_every):
    rng = np.random.default_rng(11)
    for trial in range(3):
        starts, times = _windows(case, rng, jitter=trial > 0)
        eff = None if name is None else EFFECTS.get(name)(bodies=("box",) if name == "mass" else None)
        p = None if eff is None else np.array([0.4, -1.0, 1.5, 0.2][:eff.n_params])
        mats = eff.materials(p, case.scene) if eff is not None else None
        big = tiled(case.scene, len(starts))
        new = lockstep.run_lockstep([SimWorld(case.scene, a, b, mats) for a, b in starts], times, 1e-3,
                                    eff.prepare(p, big) if eff is not None else None, kick_every)
        old = _old_lockstep([SimWorld(case.scene, a, b, mats) for a, b in starts], times, 1e-3,
                            eff.prepare(p, big) if eff is not None else None, kick_every)
        for a, b in zip(new, old, strict=True):
            assert a.shape == b.shape
            assert a.tobytes() == b.tobytes()


def test_segments_take_every_substep_once_in_order():
    rng = np.random.default_rng(4)
    times = [np.cumsum(np.r_[0.0, rng.uniform(0.0004, 0.02, n)]) for n in (0, 9, 14, 3, 14)]
    keys = tuple((t.tobytes(), 1e-3) for t in times)
    for k_kick in (0, 1, 4, 5):
        sched = _segments(keys, k_kick)
        got: dict[int, list[float]] = {i: [] for i in range(len(times))}
        reads: dict[int, list[int]] = {i: [] for i in range(len(times))}
        for a, n_act, n_sub, lo, hi, rd in sched.segments:
            assert hi - lo == n_act * n_sub
            for w, i in enumerate(sched.order[:n_act]):
                got[i] += sched.h[lo + w * n_sub:lo + (w + 1) * n_sub]
            for i in rd:
                reads[i].append(a + n_sub)
            if k_kick:  # a kick falls on a segment's start, never inside one
                assert all((a + j) % k_kick for j in range(1, n_sub))
        for i, t in enumerate(times):
            h, ends, _ = _plan(t.tobytes(), 1e-3)
            assert got[i] == list(h)
            assert reads[i] == list(ends)


def test_the_collector_is_left_as_it_was():
    case = make_case(np.random.default_rng(2), "none", episodes=1, duration=0.5)
    start, t = local_state(case.episodes[0], 3)[:2], case.episodes[0].t[3:40]
    eff = EFFECTS.get("quadratic_drag")()
    assert gc.isenabled()
    run_many(case.scene, [start], [t], 1e-3, eff, np.array([0.1]))
    assert gc.isenabled()
    gc.disable()
    try:
        run_many(case.scene, [start], [t], 1e-3, eff, np.array([0.1]))
        assert not gc.isenabled()
    finally:
        gc.enable()
    with pytest.raises(ValueError):  # an error inside still gives the collector back
        run_many(case.scene, [start], [t], 1e-3, eff, np.array([0.1, 0.2]))
    assert gc.isenabled()


def test_nominal_replicates_are_those_simulated_one_by_one(case):
    sigma, phi = noise_model(case.episodes)
    got = null_like(case.scene, case.episodes, sigma, np.random.default_rng(3), 1e-3, phi)
    rng = np.random.default_rng(3)
    for ep, new in zip(case.episodes, got, strict=True):
        pose0, vel0, _ = local_state(ep, 0, None, 1e-3)  # the simulator's own start velocity
        old = simulate_episode(case.scene, ep.id, ep.t, pose0, vel0, None, None, sigma, rng, 1e-3, phi)
        assert new.pose.tobytes() == old.pose.tobytes() and new.t.tobytes() == old.t.tobytes() and new.id == old.id
