"""What the bench conceals: one library effect, two at once, or physics outside the library.

Why a registry-driven list: each effect declares its own bench prior and scene
(``Effect.bench_prior``, ``Effect.bench_scene``), so a new effect joins the bench by being
registered. Compound truths hide two effects at once; out-of-library truths hide physics the
library cannot express exactly (a floor patch of other friction built into the simulated scene
itself, a wind gusting in time), and the finder is right on them if it names the acceptable
region effect or says honestly that the mismatch is ``unexplained``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from voe.gap.effects import EFFECTS
from voe.gap.effects.base import Effect, EffectSum
from voe.sim.scenefile import SceneSpec, SimState, StaticSpec

COMPOUNDS = (("linear_drag", "restitution"), ("quadratic_drag", "friction"),
             ("constant_acceleration", "angular_damping"), ("rolling_resistance", "mass"))
OUTSIDE = {"floor_patch": ("friction_region",), "gust": ()}  # truth -> library names that count as right


def single_truths() -> tuple[str, ...]:
    """``none`` and every registered effect with a bench scene."""
    return ("none",) + tuple(n for n in EFFECTS.ids() if EFFECTS.get(n).bench_scene is not None)


def compound_truths() -> tuple[str, ...]:
    return tuple("+".join(c) for c in COMPOUNDS)


def scene_kind(truth: str) -> str:
    """The bench scene a truth is concealed in: a single effect's own ``bench_scene``, else the
    arena (clean, compound and out-of-library cases)."""
    if kind(truth) == "single" and truth != "none":
        return EFFECTS.get(truth).bench_scene or "arena"
    return "arena"


def kind(truth: str) -> str:
    """``single``, ``compound`` or ``outside``."""
    return "outside" if truth in OUTSIDE else "compound" if "+" in truth else "single"


@dataclass(frozen=True)
class Hidden:
    """The concealed physics of one case: a scene to simulate (may differ from the nominal one),
    an effect with parameters (None for none), and the true parameters per library name."""

    sim_scene: SceneSpec
    effect: Effect | None
    params: np.ndarray
    true: dict[str, tuple[np.ndarray, tuple[str, ...] | None]]


class Gust(Effect):
    """A wind along x that gusts in time: a = A sin(2 pi t / T + phase). Bench only, not registered.

    The simulator's force callback gets no time, so the gust counts its kicks (one every 4 ms,
    ``voe.gap.rollout.KICK_EVERY``); a new instance starts every episode at t = 0.
    """

    name = "gust"
    param_names = ("A", "T", "phase")

    def __init__(self) -> None:
        super().__init__(None)
        self._n = 0

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        from voe.gap.rollout import KICK_EVERY

        t = self._n * KICK_EVERY
        self._n += 1
        a = p[0] * np.sin(2 * np.pi * t / p[1] + p[2])
        f = np.zeros_like(state.pos)
        f[:, 0] = state.mass * a
        return f, np.zeros_like(state.angle)


def hide(truth: str, scene: SceneSpec, rng: np.random.Generator) -> Hidden:
    """Draw the concealed physics ``truth`` for the nominal ``scene``."""
    if truth == "none":
        return Hidden(scene, None, np.zeros(0), {})
    if truth == "floor_patch":
        a, w = rng.uniform(-1.0, 0.5), rng.uniform(0.8, 1.5)
        mu = rng.choice([rng.uniform(2.5, 3.0), rng.uniform(0.1, 0.2)])
        floor, *walls = scene.statics
        segs = (StaticSpec((floor.a[0], 0.0), (a, 0.0), 0.0, floor.friction, floor.elasticity),
                StaticSpec((a, 0.0), (a + w, 0.0), 0.0, float(mu), floor.elasticity),
                StaticSpec((a + w, 0.0), (floor.b[0], 0.0), 0.0, floor.friction, floor.elasticity))
        sim = SceneSpec(scene.gravity, scene.bodies, segs + tuple(walls), scene.joints, scene.units)
        return Hidden(sim, None, np.zeros(0), {"friction_region": (np.array([np.nan, a, a + w]), None)})
    if truth == "gust":
        p = np.array([rng.uniform(0.6, 1.2), rng.uniform(0.8, 1.5), rng.uniform(0, 2 * np.pi)])
        return Hidden(scene, Gust(), p, {})
    names = truth.split("+")
    parts, params, true = [], [], {}
    for n in names:
        p, bodies = EFFECTS.get(n)().bench_prior(scene, rng)
        parts.append(EFFECTS.get(n)(bodies=bodies))
        params.append(p)
        true[n] = (p, bodies)
    effect = parts[0] if len(parts) == 1 else EffectSum(tuple(parts))
    return Hidden(scene, effect, np.concatenate(params), true)
