"""What a pivot joint loses: torques on the *relative* rotation of the two bodies it joins.

Why: ``angular_damping`` acts on a body's absolute rotation, which is right for a body pivoted to
the world but wrong for a joint between two moving bodies (the elbow of a double pendulum): a
bearing resists the rate at which the two bodies turn against each other, and pushes back on
both. Two laws: viscous (``joint_damping``, torque -c w_rel) and dry Coulomb friction
(``joint_friction``, torque of constant size against w_rel, smoothed below ``W0`` so that it
vanishes at rest instead of chattering). Both act on every pivot joint of the scene.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.sim.scenefile import SceneSpec, SimState

W0 = 0.05  # rad/s, smoothing rate of the dry-friction direction


def joint_pairs(scene: SceneSpec) -> list[tuple[int, int]]:
    """(a, b) body indices of every joint; b = -1 for a pivot to the world."""
    index = {n: i for i, n in enumerate(scene.names)}
    return [(index[j.a], index[j.b] if j.b is not None else -1) for j in scene.joints]


def pivot_inertia(scene: SceneSpec) -> float:
    """Mean moment of inertia of jointed bodies about their pivot (kg m^2)."""
    vals = [b.moment_value() + b.mass * float(np.sum(np.square(j.anchor_a)))
            for j in scene.joints for b in scene.bodies if b.name == j.a]
    return float(np.mean(vals)) if vals else 1e-3


def gravity_torque(scene: SceneSpec) -> float:
    """Typical gravitational torque m |g| arm about a pivot (N m): the scale of a dry friction."""
    g = float(np.linalg.norm(scene.gravity)) or 9.81
    vals = [b.mass * g * float(np.linalg.norm(j.anchor_a)) for j in scene.joints for b in scene.bodies if b.name == j.a]
    return max(float(np.mean(vals)) if vals else 0.0, 1e-6)


class _JointTorque(Effect):
    """Base: a torque law ``_law(w_rel, p)`` applied with opposite signs to the two joined bodies."""

    acts = "joint"
    contexts = ("swinging",)
    flight_regression = False
    bench_scene = "double_pendulum"  # voe.gap.bench_pendulum: the arena has no joints

    @property
    def has_forces(self) -> bool:
        return True

    def _law(self, w_rel: np.ndarray, p: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def applies(self, scene: SceneSpec) -> bool:
        return bool(scene.joints)

    def prepare(self, params: np.ndarray, scene: SceneSpec) -> Callable[[SimState], tuple[np.ndarray, np.ndarray]]:
        p, pairs = self.check(params), joint_pairs(scene)
        a = np.array([i for i, _ in pairs], dtype=int)
        b = np.array([j for _, j in pairs], dtype=int)
        world = b < 0

        def torque(st: SimState) -> tuple[np.ndarray, np.ndarray]:
            w_rel = st.omega[a] - np.where(world, 0.0, st.omega[b])  # (J,)
            t = self._law(w_rel, p)
            tau = np.zeros_like(st.omega)
            np.add.at(tau, a, t)
            np.add.at(tau, b[~world], -t[~world])
            return np.zeros_like(st.pos), tau

        return torque

    def forces(self, state: SimState, params: np.ndarray, scene: SceneSpec) -> tuple[np.ndarray, np.ndarray]:
        return self.prepare(params, scene)(state)

    def _forces(self, state: SimState, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # without the scene no joint is known: free bodies (all that prefit sees) feel nothing
        return np.zeros_like(state.pos), np.zeros_like(state.angle)


class JointDamping(_JointTorque):
    name = "joint_damping"
    param_names = ("c",)
    units = ("N m s/rad",)
    summary = "pivot joints are damped in proportion to the relative rotation rate (viscous bearing)"

    def applies(self, scene: SceneSpec) -> bool:
        # on a pivot to the world it is angular_damping of that body: not a separate candidate
        return any(j.b is not None for j in scene.joints)

    def _law(self, w_rel: np.ndarray, p: np.ndarray) -> np.ndarray:
        return -p[0] * w_rel

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        """c / I of 0.3-0.8 /s: the swing's relative motion decays by a few tens of per cent in 3 s
        (several mm of position against 1 mm noise), far from stopping it."""
        return np.array([pivot_inertia(scene) * rng.uniform(0.3, 0.8)]), None

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([1e-3 * pivot_inertia(ctx.scene)])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([0.1 * pivot_inertia(ctx.scene)])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([1e3 * pivot_inertia(ctx.scene)])


class JointFriction(_JointTorque):
    name = "joint_friction"
    param_names = ("tau_c",)
    units = ("N m",)
    summary = "pivot joints resist turning with a constant torque (dry, Coulomb bearing friction)"

    def _law(self, w_rel: np.ndarray, p: np.ndarray) -> np.ndarray:
        return -p[0] * w_rel / np.sqrt(w_rel**2 + W0**2)

    def bench_prior(self, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
        """1-3 % of the gravity torque: a bearing that visibly slows the swing without locking it."""
        return np.array([gravity_torque(scene) * rng.uniform(0.01, 0.03)]), None

    def starts(self, ctx: FitContext) -> list[np.ndarray]:
        return [np.array([1e-4 * gravity_torque(ctx.scene)])]

    def scale(self, ctx: FitContext) -> np.ndarray:
        return np.array([1e-3 * gravity_torque(ctx.scene)])

    def bounds(self, ctx: FitContext) -> tuple[np.ndarray, np.ndarray]:
        return np.array([0.0]), np.array([gravity_torque(ctx.scene)])
