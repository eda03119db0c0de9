"""Simulate recordings: the clean null data for calibration and the concealed-effect bench data.

Why: the acceptance threshold must come from what the finder does on data where nothing is
missing. Simulating the nominal scene from each recorded episode's own initial state, with the
noise floor measured on the real data, gives exactly that null, at the same sampling and length.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.recordings import Episode
from voe.gap.shooting import local_state
from voe.sim.scenefile import SceneSpec, SimWorld


def simulate_episode(scene: SceneSpec, ep_id: int, t: np.ndarray, pose0: np.ndarray, vel0: np.ndarray,
                     effect: Effect | None, params: np.ndarray | None, sigma: np.ndarray,
                     rng: np.random.Generator, substep: float = 1e-3) -> Episode:
    """One episode (T samples at ``t``) with Gaussian noise ``sigma`` (B, 3) added to the poses."""
    mats = effect.materials(params, scene) if effect is not None else None
    world = SimWorld(scene, pose0, vel0, mats)
    force_fn = None
    if effect is not None and effect.has_forces:
        def force_fn(state):
            return effect.forces(state, params, scene)
    pose = world.run(t, substep, force_fn)  # (T, B, 3)
    return Episode(ep_id, t.copy(), pose + rng.normal(size=pose.shape) * sigma[None])


def null_like(scene: SceneSpec, episodes: list[Episode], sigma: np.ndarray, rng: np.random.Generator,
              substep: float) -> list[Episode]:
    """Clean copies of ``episodes``: nominal simulation from each one's estimated initial state."""
    out = []
    for ep in episodes:
        pose0, vel0, _ = local_state(ep, 0)
        out.append(simulate_episode(scene, ep.id, ep.t, pose0, vel0, None, None, sigma, rng, substep))
    return out
