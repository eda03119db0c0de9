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
against the restitution the object has shown. Friction is a fixed model argument.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.special import logsumexp

from voe.errors import ModelContractError
from voe.io.batch import Batch
from voe.models import statelik as sl
from voe.models.point import PointPredictorAdapter
from voe.sim.rollout import visible_slots
from voe.sim.scene import Body, Scene, geometry_from_dict
from voe.sim.world import World

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
        refine: hypotheses per grid interval (``refine - 1`` interpolated between neighbours).
    """

    def __init__(self, noise: dict[str, Any] | None = None, elasticity: float | list[float] | None = None,
                 friction: float = 0.0, substeps: int = 10, p_visible: float = 0.99, refine: int = 4) -> None:
        super().__init__(lambda s, dt, n: s, noise, name="oracle")
        grid = ELASTICITY_GRID if elasticity is None else np.atleast_1d(np.asarray(elasticity, dtype=float))
        self.elasticities = tuple(sorted(float(e) for e in grid))
        self.friction = float(friction)
        self.substeps, self.p_visible, self.refine = int(substeps), float(p_visible), int(refine)
        self.bounce_speed = sl.QUANTUM[sl.CONT.index("vy")]

    def config(self) -> dict[str, Any]:
        return {**super().config(), "elasticity": list(self.elasticities), "friction": self.friction,
                "substeps": self.substeps, "p_visible": self.p_visible, "refine": self.refine}

    # -- the protocol ----------------------------------------------------------------------------
    def frame_nll(self, batch: Batch) -> np.ndarray:
        mean, kind, circ, pp, contact = self._predict(batch)
        nll = self._hypothesis_nll(batch, mean, kind, circ, pp, contact, self.noise, self._shape_prior(kind))
        H, B, T, K = nll.shape
        per_slot = mixture_nll(nll.transpose(0, 1, 3, 2).reshape(H, B * K, T))  # (B * K, T), frame 0 NaN
        return per_slot.reshape(B, K, T).sum(axis=1)

    def calibrate(self, batch: Batch) -> sl.Noise:
        """Fit the noise by maximum likelihood, each clip scored under its best hypothesis."""
        mean, kind, circ, pp, contact = self._predict(batch)
        noise = self.noise
        rows, slots = np.arange(len(batch))[:, None], np.arange(kind.shape[-1])[None, :]
        for _ in range(2):  # which hypothesis fits best depends on the noise, and vice versa
            nll = self._hypothesis_nll(batch, mean, kind, circ, pp, contact, noise)  # (H, B, T, K)
            best = np.nansum(nll, axis=2).argmin(0)  # (B, K): each object's own best
            m = mean.transpose(0, 3, 1, 2, 4)[rows, slots, best].transpose(0, 2, 1, 3)  # (B, T, K, 9)
            c = contact.transpose(0, 3, 1, 2)[rows, slots, best].transpose(0, 2, 1)  # (B, T, K)
            noise = sl.fit_noise(batch, m, kind, circ, c)
        self.noise = noise
        return noise

    # -- internals -------------------------------------------------------------------------------
    def _hypothesis_nll(self, batch: Batch, mean: np.ndarray, kind: np.ndarray, circ: np.ndarray,
                        pp: np.ndarray, contact: np.ndarray, noise: sl.Noise,
                        shape_prior: np.ndarray | None = None) -> np.ndarray:
        """Per-frame surprise of each slot under each hypothesis alone, ``(H, B, T, K)``."""
        return np.stack([sl.score(batch, mean[:, h], kind, noise, pp[:, h], circ, contact[:, h], shape_prior,
                                  per_slot=True) for h in range(mean.shape[1])])

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
        geo = self._geometry(geo)
        statics, occluders = geometry_from_dict(geo)
        extent = tuple(geo.get("extent", (10.0, 10.0)))
        # an object within a pixel of a screen's edge is drawn (anti-aliasing), so it is present
        env = (statics, occluders, tuple(geo.get("gravity", (0.0, -9.81))), extent, dt, ix, extent[0] / width_px)
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
                pvis[:, t + 1, k] = np.where(vis[:, k], self.p_visible, 1 - self.p_visible)
            pred[:, t + 1] = cur
            cur[:, self._forget(present[t + 1])] = np.nan
            self._unseen(cur, ~present[t + 1], ix)
        return pred, pvis, contact

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

    def _predict(self, batch: Batch):
        """Per hypothesis: means ``(B, H, T, K, 9)``, kinds ``(B, T, K)``, remembered shapes
        ``(B, T, K)``, P(present) ``(B, H, T, K)`` and impacts ``(B, H, T, K)``."""
        if len(batch.geometry) != len(batch):
            raise ModelContractError("oracle needs batch.geometry (static segments and screens) per clip")
        names = batch.feature_names
        idx = sl.cont_index(names)
        states = batch.states.astype(np.float64)
        out = [self._clip(states[b], batch.present[b], batch.geometry[b], batch.dt, names, batch.frames.shape[-1])
               for b in range(len(batch))]
        pred, pvis, contact = refine(np.stack([o[0] for o in out]),  # (B, H, T, K, F)
                                     np.stack([o[1] for o in out]),  # (B, H, T, K)
                                     np.stack([o[2] for o in out]),  # (B, H, T, K)
                                     self.refine, names.index("angle"))
        known = np.zeros(batch.present.shape, dtype=bool)
        known[:, 1:] = ~np.isnan(pred[:, 0, 1:, :, 0])
        kind = sl.slot_kind(np.cumsum(batch.present, axis=1) > 0, batch.present)
        pp = np.where((kind == sl.NEW)[:, None], self.noise.p_present[sl.NEW], pvis)
        circ = np.zeros(kind.shape, dtype=bool)
        circ[:, 1:] = pred[:, 0, 1:, :, names.index("is_circle")] > 0.5
        return pred[..., idx], kind, circ, pp, contact


def refine(pred: np.ndarray, pvis: np.ndarray, contact: np.ndarray, k: int,
           angle: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Put ``k - 1`` hypotheses between each two neighbours of the grid, by interpolation.

    Why: a calibrated oracle predicts unhurried frames to within a fraction of the observation
    grid, so at an impact a grid of 0.05 in elasticity (about 0.3 units/s in a rebound) is coarse
    enough for the luck of which clip lies nearer a grid point to decide a comparison. What one
    impact does to the state is smooth in the elasticity, so the in-between predictions are
    interpolated instead of simulated (visibility is taken from the nearer neighbour).

    Args:
        pred: ``(B, H, T, K, F)``; pvis, contact: ``(B, H, T, K)``; angle: index of the angle
            feature (interpolated along the shorter way round).

    Returns:
        The same arrays with ``(H - 1) * k + 1`` hypotheses, the originals at every k-th.
    """
    if k <= 1 or pred.shape[1] < 2:
        return pred, pvis, contact
    lo, hi = pred[:, :-1], pred[:, 1:]
    step = hi - lo
    step[..., angle] = (step[..., angle] + np.pi) % (2 * np.pi) - np.pi
    fr = np.arange(k) / k  # (k,)
    mid = lo[:, :, None] + step[:, :, None] * fr[None, None, :, None, None, None]  # (B, H-1, k, T, K, F)
    near = fr < 0.5
    vis = np.where(near[None, None, :, None, None], pvis[:, :-1, None], pvis[:, 1:, None])
    hit = (contact[:, :-1] | contact[:, 1:])[:, :, None].repeat(k, axis=2)
    hit[:, :, 0] = contact[:, :-1]
    B, H = pred.shape[:2]

    def flat(a: np.ndarray, last: np.ndarray) -> np.ndarray:
        return np.concatenate([a.reshape(B, (H - 1) * k, *a.shape[3:]), last[:, -1:]], axis=1)

    return flat(mid, pred), flat(vis, pvis), flat(hit, contact)


def mixture_nll(nll: np.ndarray) -> np.ndarray:
    """Per-frame surprise ``(B, T)`` of an equal-weight Bayesian mixture of hypotheses.

    Args:
        nll: ``(H, B, T)`` per-frame surprise under each hypothesis alone (frame 0 NaN).

    Returns:
        ``-log p(o_t | o_<t)``, where the mixture weights at t are the hypotheses' posteriors
        given frames 1..t-1; frame 0 NaN.
    """
    H = nll.shape[0]
    cum = np.cumsum(np.nan_to_num(nll, nan=0.0), axis=-1)  # (H, B, T): -log p(o_1..t | h)
    log_evidence = logsumexp(-cum, axis=0) - np.log(H)  # (B, T): log p(o_1..t)
    out = -np.diff(log_evidence, axis=-1, prepend=0.0)
    out[:, 0] = np.nan
    return out
