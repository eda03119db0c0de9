"""Simulate recordings: the clean null data for calibration and the concealed-effect bench data.

Why: the acceptance threshold must come from what the finder does on data where nothing is
missing. Simulating the nominal scene from each recorded episode's own initial state, with the
noise floor measured on the real data, gives exactly that null, at the same sampling and length.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.jitter import Jitter, jitter_noise
from voe.gap.recordings import Episode
from voe.gap.shooting import local_state
from voe.sim.lockstep import run_lockstep
from voe.sim.scenefile import SceneSpec, SimWorld


def ar1_noise(shape: tuple[int, ...], sigma: np.ndarray, phi: np.ndarray | float, rng: np.random.Generator) -> np.ndarray:
    """(T, B, 3) stationary AR(1) noise of marginal ``sigma`` (B, 3) and coefficient ``phi``."""
    phi = np.broadcast_to(np.asarray(phi, float), sigma.shape)
    e = rng.normal(size=shape)
    out = np.empty(shape)
    out[0] = e[0]
    inno = np.sqrt(1 - phi**2)
    for k in range(1, shape[0]):
        out[k] = phi * out[k - 1] + inno * e[k]
    return out * sigma[None]


def simulate_episode(scene: SceneSpec, ep_id: int, t: np.ndarray, pose0: np.ndarray, vel0: np.ndarray,
                     effect: Effect | None, params: np.ndarray | None, sigma: np.ndarray,
                     rng: np.random.Generator, substep: float = 1e-3, phi: np.ndarray | float = 0.0) -> Episode:
    """One episode (T samples at ``t``) with noise ``sigma`` (B, 3), AR(1) with ``phi``, added to the poses."""
    mats = effect.materials(params, scene) if effect is not None else None
    world = SimWorld(scene, pose0, vel0, mats)
    force_fn = None
    if effect is not None and effect.has_forces:
        def force_fn(state):
            return effect.forces(state, params, scene)
    pose = world.run(t, substep, force_fn)  # (T, B, 3)
    return Episode(ep_id, t.copy(), pose + pose_noise(pose.shape, sigma, phi, rng))


def pose_noise(shape: tuple[int, ...], sigma: np.ndarray, phi: np.ndarray | float, rng: np.random.Generator) -> np.ndarray:
    """(T, B, 3) measurement noise of the data's noise model: white (one normal draw per sample)
    where every ``phi`` is 0, else AR(1) (``ar1_noise``)."""
    if np.all(np.asarray(phi) == 0):
        return rng.normal(size=shape) * sigma[None]
    return ar1_noise(shape, sigma, phi, rng)


def replicate_noise(clean: np.ndarray, t: np.ndarray, sigma: np.ndarray, phi: np.ndarray | float,
                    jitter: Jitter | None, rng: np.random.Generator) -> np.ndarray:
    """(T, B, 3) the data's noise model drawn for a clean replicate's poses ``clean`` (T, B, 3) at
    ``t`` (T,): ``pose_noise`` of ``sigma`` (B, 3) and ``phi``, or, when the recordings show timing
    jitter (``voe.gap.jitter``), the sensor noise beneath it plus the jitter's error (the jitter
    draws come after the sensor's, so without jitter the draws are exactly ``pose_noise``'s)."""
    if jitter is None:
        return pose_noise(clean.shape, sigma, phi, rng)
    return pose_noise(clean.shape, jitter.sensor, phi, rng) + jitter_noise(clean, t, jitter.seconds, rng)


def null_like(scene: SceneSpec, episodes: list[Episode], sigma: np.ndarray, rng: np.random.Generator,
              substep: float, phi: np.ndarray | float = 0.0, jitter: Jitter | None = None) -> list[Episode]:
    """Clean copies of ``episodes``: nominal simulation from each one's estimated initial state,
    with the data's noise model (``voe.gap.shooting.noise_model``, ``replicate_noise``); without
    jitter the same episodes as ``simulate_episode`` makes one by one (the same motion, then the
    noise drawn in episode order)."""
    return [Episode(ep.id, ep.t.copy(), m + replicate_noise(m, ep.t, sigma, phi, jitter, rng))
            for ep, m in zip(episodes, nominal_motion(scene, episodes, substep), strict=True)]


def nominal_motion(scene: SceneSpec, episodes: list[Episode], substep: float) -> list[np.ndarray]:
    """(T, B, 3) noise-free nominal poses of each episode from its estimated initial state.

    Why not ``SimWorld.run`` one episode after the other: all episodes stepped side by side
    (``voe.sim.lockstep``) take the same substeps in C, each exactly as ``SimWorld.run`` steps
    it alone, without pymunk's ``Space.step`` wrapper around every substep. The clean replicate
    is simulated before the search can start, so its time is wall time.
    """
    worlds = []
    for ep in episodes:
        pose0, vel0, _ = local_state(ep, 0, None, substep)
        worlds.append(SimWorld(scene, pose0, vel0))
    return run_lockstep(worlds, [ep.t for ep in episodes], substep)
