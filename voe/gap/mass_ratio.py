"""A per-body mass on every body is one parameter too many: only mass ratios are seen.

Why: gravity, contact impulses (friction, restitution) and every force law that acts in
proportion to a body's mass (``Effect.mass_proportional``: an acceleration field, a drag per unit
mass, rolling resistance) leave a motion unchanged when every body's mass and moment are scaled by
one factor. A model that puts a ``mass`` on every body of the scene, with nothing else in it that
sees absolute masses (a damping torque -b omega does), has a direction in which the prediction
does not change at all; what a fit gains by adding the last body's mass is only what a better fit
of the first mass would have gained. Development case 5905133 (true ``rolling_resistance`` and the
box's mass x0.392; seed 5905's paired bench of session 66, ``docs/bench-runs/dev-s66/trace_5905133.txt``):
round 1 accepted ``mass[box]`` 0.536 (its interval 0.386-0.642 holds the truth), a later round
``mass[ball]`` 1.285 for a gain of 51 %, and the report named three effects, two of them masses
whose ratio (0.417) is the one thing the recordings fix.

So a round does not offer a candidate whose model would put a mass on every body while all its
parts are mass-proportional (``one_too_many``), in the data's search and the null's alike
(``voe.gap.search.fit_rounds``), nor does the re-selection ask such a swap (``voe.gap.reselect``).
A mass on every body but one still says everything the recordings can: the ratios.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.effects.mass import Mass
from voe.gap.folds import FoldedFitter
from voe.sim.scenefile import SceneSpec


def one_too_many(scene: SceneSpec, parts: tuple[Effect, ...]) -> bool:
    """Whether the model made of ``parts`` scales the mass of every body of ``scene`` (two or more)
    and every part is ``mass_proportional``, so that one mass is not identifiable."""
    masses = [e for e in parts if isinstance(e, Mass)]
    if len(scene.bodies) < 2 or not masses or not all(e.mass_proportional for e in parts):
        return False
    covered = np.logical_or.reduce([e.mask(scene) for e in masses])  # (B,)
    return bool(np.all(covered))


def not_offered(fitter: FoldedFitter, parts: tuple[Effect, ...]) -> bool:
    """``one_too_many`` on the scene of ``fitter``'s shooter (read only when a mass is among ``parts``)."""
    return any(isinstance(e, Mass) for e in parts) and one_too_many(fitter.shooter.scene, parts)
