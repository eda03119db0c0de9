"""Physics oracle: re-simulate every frame in pymunk from the observed state, plus calibrated noise.

Why: it is the upper bound a learned state model can approach. For each frame it rebuilds the
clip's static segments and screens from ``batch.geometry``, places every known object at its last
observed state (or its carried state while hidden), steps one frame and predicts the next state.
Presence is predicted from the same geometry: an object whose predicted box is outside the window
or fully behind a screen should be absent (probability ``1 - p_visible``), any other known object
present. Noise is fitted by maximum likelihood like the other point predictors.

What the oracle cannot see it infers, as an ideal observer would. Mass follows the training
world's law (mass = width x height). Elasticity is not observable, so the oracle is a Bayesian
mixture over a grid of elasticity hypotheses (the floor's and walls' own elasticities are part of
the geometry): each hypothesis is a complete oracle rollout with that elasticity for every object,
and each object's surprise at frame t is ``-log p(o_t | o_<t)`` under the mixture whose weights are
the hypotheses' posteriors given that object's earlier frames (each object has its own
elasticity; two objects that hit each other are simulated with the same one, an approximation).
The first bounce is thus judged against every restitution the world allows, and later bounces
against the restitution the object has shown. The simulated grid is refined by interpolation,
clip by clip, until neighbouring hypotheses are within half an observation cell of each other
on every observed frame (``voe.models.hypotheses``); an object coming back from behind a screen
is scored with at least that much noise (``statelik.RETURN_FLOOR``). Friction is a fixed model
argument.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.errors import ModelContractError
from voe.io.batch import Batch
from voe.models import statelik as sl
from voe.models.hypotheses import interval_counts, mixture_nll, refine
from voe.models.point import PointPredictorAdapter
from voe.sim.render import visible
from voe.sim.rollout import visible_slots
from voe.sim.scene import Body, Scene, geometry_from_dict
from voe.sim.world import World

__all__ = ["ELASTICITY_GRID", "PhysicsOracle", "mixture_nll", "refine"]

#: Elasticity hypotheses: the training world draws objects' elasticity from U(0.1, 0.9); the grid
#: reaches 1.0 so that perfectly elastic objects are covered too. Every restitution it implies is
#: at most 1 (pymunk multiplies the two shapes' elasticities).
ELASTICITY_GRID = tuple(round(0.1 + 0.05 * i, 2) for i in range(19))


class PhysicsOracle(PointPredictorAdapter):
    """Reference upper bound (see the module docstring).

    Args:
        noise: calibrated noise (from ``calibrate``).
        elasticity: one elasticity, or the grid of hypotheses (default ``ELASTICITY_GRID``).
        friction: friction of every object.
        substeps: physics steps per frame.
        p_visible: P(present) of an object predicted to be in view.
        refine: least hypotheses per grid interval (``refine - 1`` interpolated between neighbours);
            more where the clip needs them (``voe.models.hypotheses``), up to ``max_refine``.
        max_refine: most hypotheses per grid interval (bounds time and memory per clip).
    """

    def __init__(self, noise: dict[str, Any] | None = None, elasticity: float | list[float] | None = None,
                 friction: float = 0.0, substeps: int = 10, p_visible: float = 0.99, refine: int = 4,
                 max_refine: int = 64) -> None:
        super().__init__(lambda s, dt, n: s, noise, name="oracle")
        grid = ELASTICITY_GRID if elasticity is None else np.atleast_1d(np.asarray(elasticity, dtype=float))
        self.elasticities = tuple(sorted(float(e) for e in grid))
        self.friction = float(friction)
        self.substeps, self.p_visible, self.refine = int(substeps), float(p_visible), int(refine)
        self.max_refine = max(int(max_refine), self.refine)
        self.bounce_speed = sl.QUANTUM[sl.CONT.index("vy")]

    def config(self) -> dict[str, Any]:
        return {**super().config(), "elasticity": list(self.elasticities), "friction": self.friction,
                "substeps": self.substeps, "p_visible": self.p_visible, "refine": self.refine,
                "max_refine": self.max_refine}

    # -- the protocol ----------------------------------------------------------------------------
    def frame_nll(self, batch: Batch) -> np.ndarray:
        """Clip by clip: each clip has its own refinement of the hypotheses."""
        out = np.full(batch.shape, np.nan)
        for b in range(len(batch)):
            one = batch.take([b])
            mean, kind, circ, pp, contact, log_prior = self._predict(one)
            nll = self._hypothesis_nll(one, mean, kind, circ, pp, contact, self.noise, self._shape_prior(kind))
            per_slot = mixture_nll(nll[:, 0].transpose(0, 2, 1), log_prior)  # (K, T), frame 0 NaN
            out[b] = per_slot.sum(axis=0)
        return out

    def calibrate(self, batch: Batch) -> sl.Noise:
        """Fit the noise by maximum likelihood, each object scored under its best hypothesis."""
        clips = [batch.take([b]) for b in range(len(batch))]
        grids = [self._simulate(one) for one in clips]  # the simulation is the slow part: once
        noise = self.noise
        for _ in range(2):  # which hypothesis fits best depends on the noise, and vice versa
            parts = []
            for one, grid in zip(clips, grids, strict=True):
                mean, kind, circ, pp, contact, _ = self._predict(one, grid)
                nll = self._hypothesis_nll(one, mean, kind, circ, pp, contact, noise)  # (H, 1, T, K)
                best = np.nansum(nll[:, 0], axis=1).argmin(0)  # (K,): each object's own best
                slots = np.arange(kind.shape[-1])
                parts.append((mean[0, best, :, slots].transpose(1, 0, 2),  # (T, K, 9)
                              kind[0], circ[0], contact[0, best, :, slots].T))  # (T, K)
            m, k, c, hit = (np.stack(a) for a in zip(*parts, strict=True))
            noise = sl.fit_noise(batch, m, k, c, hit)
        self.noise = noise
        return noise

    # -- internals -------------------------------------------------------------------------------
    def _hypothesis_nll(self, one: Batch, mean: np.ndarray, kind: np.ndarray, circ: np.ndarray,
                        pp: np.ndarray, contact: np.ndarray, noise: sl.Noise,
                        shape_prior: np.ndarray | None = None) -> np.ndarray:
        """Per-frame surprise of each slot of one clip under each hypothesis alone, ``(H, 1, T, K)``:
        the hypotheses are scored at once as a batch of H copies of the clip."""
        H = mean.shape[1]
        rep = Batch(np.broadcast_to(one.frames, (H, *one.frames.shape[1:])),
                    np.broadcast_to(one.states, (H, *one.states.shape[1:])),
                    np.broadcast_to(one.present, (H, *one.present.shape[1:])), one.feature_names, one.dt)

        def each(a: np.ndarray | None) -> np.ndarray | None:
            return None if a is None else np.broadcast_to(a, (H, *a.shape[1:]))

        nll = sl.score(rep, mean[0], each(kind), noise, pp[0], each(circ), contact[0], each(shape_prior),
                       per_slot=True)  # (H, T, K)
        return nll[:, None]

    def _body(self, slot: int, s: np.ndarray, ix: dict[str, int], elasticity: float) -> Body:
        circle = s[ix["is_circle"]] > 0.5
        w, h = max(float(s[ix["width"]]), 0.05), max(float(s[ix["height"]]), 0.05)
        h = w if circle else h
        return Body(slot=slot, shape="circle" if circle else "box", width=w, height=h,
                    x=float(s[ix["x"]]), y=float(s[ix["y"]]), angle=float(s[ix["angle"]]),
                    vx=float(s[ix["vx"]]), vy=float(s[ix["vy"]]), omega=float(s[ix["omega"]]),
                    mass=w * h, friction=self.friction, elasticity=elasticity,
                    intensity=float(s[ix["intensity"]]))

    def _step(self, cur: np.ndarray, known: list[int], elasticity: float, statics, occluders, gravity,
              extent, dt: float, ix: dict[str, int], pixel: float) -> tuple[np.ndarray, np.ndarray, float]:
        """One frame ahead from ``cur (K, F)``: next states ``(K, F)``, visibility ``(K,)`` and which
        slots had an impact (a contact approaching at ``bounce_speed`` or faster) ``(K,)``."""
        K = cur.shape[0]
        scene = Scene(tuple(self._body(k, cur[k], ix, elasticity) for k in known), statics, occluders,
                      gravity, extent)
        world = self._world(scene, dt)
        hit = np.zeros(K, dtype=bool)

        def begin(arb, space, data) -> None:
            a, b = arb.bodies
            n = arb.normal
            # approaching: an impact; separating fast: an impact that straddles the frame boundary
            fastest = max(abs((b.velocity_at_world_point(p.point_b) - a.velocity_at_world_point(p.point_a)).dot(n))
                          for p in arb.contact_point_set.points) if arb.contact_point_set.points else 0.0
            if fastest >= self.bounce_speed:
                for body in (a, b):
                    spec = getattr(body, "voe_spec", None)
                    if spec is not None:
                        hit[spec.slot] = True

        world.space.on_collision(begin=begin)
        world.step()
        nxt = world.observe(K).astype(np.float64)
        vis = visible_slots(world, scene, pixel)
        return nxt, np.array([bool(vis.get(k, False)) for k in range(K)]), hit

    def _clip(self, states: np.ndarray, present: np.ndarray, geo: dict[str, Any], dt: float,
              names: tuple[str, ...], width_px: int) -> tuple[np.ndarray, np.ndarray]:
        """Predictions ``(H, T, K, F)`` (NaN for unknown slots), P(present) ``(H, T, K)`` and
        impacts ``(H, T, K)`` (the prediction of frame t went through one).

        Hypotheses that carry the same state are stepped once, and one by one only when a contact
        approaches faster than ``bounce_speed``: below it, elasticity moves the outcome by less
        than the observation grid's velocity cell (0.05 units/s).
        """
        T, K, F = states.shape
        E = self.elasticities
        H = len(E)
        ix = {n: i for i, n in enumerate(names)}
        statics, occluders, gravity, extent, pixel = self._view(geo, width_px)
        env = (statics, occluders, gravity, extent, dt, ix, pixel)
        pred = np.full((H, T, K, F), np.nan)
        pvis = np.full((H, T, K), np.nan)
        contact = np.zeros((H, T, K), dtype=bool)
        cur = np.full((H, K, F), np.nan)
        for t in range(T - 1):
            cur[:, present[t]] = states[t][present[t]]
            known = [k for k in range(K) if not np.isnan(cur[0, k, 0])]
            if not known:
                continue
            groups: dict[bytes, list[int]] = {}
            for h in range(H):
                groups.setdefault(cur[h, known].tobytes(), []).append(h)
            nxt, vis, hit = np.empty((H, K, F)), np.empty((H, K), dtype=bool), np.empty((H, K), dtype=bool)
            for members in groups.values():
                first = members[0]
                nxt[first], vis[first], hit[first] = self._step(cur[first], known, E[first], *env)
                for h in members[1:]:
                    if not hit[first].any():  # no impact: elasticity changes nothing seen
                        nxt[h], vis[h], hit[h] = nxt[first], vis[first], hit[first]
                    else:
                        nxt[h], vis[h], hit[h] = self._step(cur[h], known, E[h], *env)
            contact[:, t + 1] = hit
            for k in known:
                cur[:, k] = nxt[:, k]
                pvis[:, t + 1, k] = self._p_present(vis[:, k])
            pred[:, t + 1] = cur
            cur[:, self._forget(present[t + 1])] = np.nan
            self._unseen(cur, ~present[t + 1], ix)
        return pred, pvis, contact

    def _view(self, geo: dict[str, Any], width_px: int) -> tuple[Any, Any, tuple[float, float], tuple[float, float], float]:
        """The clip's world as this oracle sees it (``_geometry``: a lesion may change it): statics,
        occluders, gravity, extent and the pixel size (an object within a pixel of a screen's edge
        is drawn, anti-aliased, so it is present)."""
        geo = self._geometry(geo)
        statics, occluders = geometry_from_dict(geo)
        extent = tuple(geo.get("extent", (10.0, 10.0)))
        return statics, occluders, tuple(geo.get("gravity", (0.0, -9.81))), extent, extent[0] / width_px

    def _p_present(self, vis: np.ndarray) -> np.ndarray:
        """P(present) of objects predicted visible (``vis`` bool) or not."""
        return np.where(vis, self.p_visible, 1 - self.p_visible)

    # -- hooks for lesioned variants (voe.controls.lesions) ---------------------------------
    def _geometry(self, geo: dict[str, Any]) -> dict[str, Any]:
        """The clip geometry the oracle simulates in (a lesion may drop gravity)."""
        return geo

    def _world(self, scene: Scene, dt: float) -> World:
        """The world that predicts one frame ahead (a lesion may change its laws)."""
        return World(scene, dt, self.substeps)

    def _forget(self, present_t: np.ndarray) -> np.ndarray:
        """Slots whose memory is dropped after frame t, ``(K,)`` bool: none for the intact oracle."""
        return np.zeros_like(present_t)

    def _unseen(self, cur: np.ndarray, hidden: np.ndarray, ix: dict[str, int]) -> None:
        """Edit in place the carried states ``(H, K, F)`` of slots out of sight ``(K,)``: the
        intact oracle remembers them as they were."""

    def _shape_prior(self, kind: np.ndarray) -> np.ndarray | None:
        """Known slots ``(B, T, K)`` whose shape and size are scored like a new object's: none
        for the intact oracle (a lesion may forget them)."""
        return None

    def _simulate(self, one: Batch) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The simulated grid of one clip: predictions ``(H, T, K, F)``, P(present) and impacts
        ``(H, T, K)`` (see ``_clip``)."""
        if len(one.geometry) != len(one):
            raise ModelContractError("oracle needs batch.geometry (static segments and screens) per clip")
        return self._clip(one.states[0].astype(np.float64), one.present[0], one.geometry[0], one.dt,
                          one.feature_names, one.frames.shape[-1])

    def _predict(self, one: Batch, grid: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None):
        """Per hypothesis of one clip: means ``(1, H, T, K, 9)``, kinds ``(1, T, K)``, remembered
        shapes ``(1, T, K)``, P(present) ``(1, H, T, K)``, impacts ``(1, H, T, K)`` and the log
        prior weights ``(H,)``, the grid refined as ``voe.models.hypotheses`` explains.

        Args:
            one: a batch of one clip.
            grid: ``_simulate(one)``, if already computed.
        """
        names = one.feature_names
        idx = sl.cont_index(names)
        pred, pvis, contact = self._simulate(one) if grid is None else grid
        _, occluders, _, extent, pixel = self._view(one.geometry[0], one.frames.shape[-1])

        def p_vis(s: np.ndarray) -> np.ndarray:
            return self._p_present(visible(s, occluders, extent, pixel))

        scored = one.present[0].copy()  # (T, K) compared with an observation
        scored[0] = False
        dyn = [idx[i] for i, f in enumerate(sl.RETURN_FLOOR) if f > 0]
        spacing = np.asarray([f for f in sl.RETURN_FLOOR if f > 0])
        counts = interval_counts(pred, scored, dyn, spacing, names.index("angle"), self.refine, self.max_refine)
        pred, pvis, contact, log_prior = refine(pred, pvis, contact, counts, self.elasticities,
                                                names.index("angle"), p_vis)
        kind = sl.slot_kind(np.cumsum(one.present, axis=1) > 0, one.present)  # (1, T, K)
        pp = np.where(kind == sl.NEW, self.noise.p_present[sl.NEW], pvis)[None]  # (1, H, T, K)
        circ = np.zeros(kind.shape, dtype=bool)
        circ[:, 1:] = pred[0, 1:, :, names.index("is_circle")] > 0.5
        return pred[None][..., idx], kind, circ, pp, contact[None], log_prior
