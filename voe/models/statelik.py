"""The state observation space and its likelihood, shared by every state model.

Observation space of one frame: for each of the K slots either *absent*, or *present* with a
shape in {circle, box} and the continuous features ``CONT`` quantised to the grid ``QUANTUM``
(0.01 scene units for positions, a fifth of a pixel). A state model predicts, per slot, a presence
probability, a shape probability and a diagonal Gaussian over ``CONT``, integrated over each
observed value's grid cell; the frame's surprise is the sum over slots of

    -log P(present) [- log P(shape) - sum_f log P(cell_f; mu_f, sigma_f)]   (bracket only when present)

a normalised distribution over a discrete space, so every term is >= 0. Why discrete: with a
density, a well-predicted visible object earns a *negative* surprise (tens of nats) that an
absent one does not, so clips would differ in surprise merely by how long objects are in view.
Each Gaussian is mixed with an outlier component (weight ``OUTLIER`` = 1% for the references,
learned for the networks), uniform over a generous ``RANGE``, so that one mispredicted contact
cannot dominate a clip: a wrong feature costs at most about ``log(1 / w) + log(range / cell)``.
The angle residual is wrapped to (-pi, pi] (negligible tail mass for sigma << pi). ``is_box`` is
``1 - is_circle`` and is therefore not scored.

Memory: each slot carries its last observed state forward while it is absent (``carry``), so an
object that reappears from behind a screen is scored against where it should be now.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from voe.errors import ModelContractError
from voe.io.batch import Batch

CONT = ("x", "y", "angle", "vx", "vy", "omega", "width", "height", "intensity")
CONSTANT = ("width", "height", "intensity")  # an object's look never changes
_SHAPE = np.isin(CONT, ("width", "height"))  # (9,) the features ``score(shape_prior=...)`` forgets
#: Resolution of the state observation space per ``CONT`` feature.
QUANTUM = (0.01, 0.01, 0.01, 0.05, 0.05, 0.05, 0.01, 0.01, 0.01)
#: Smallest noise of the dynamic features of a slot predicted through something unobserved: one
#: coming back from behind a screen (``sigma_return``) or one through an impact (``sigma_contact``,
#: whose outcome depends on an elasticity no frame shows): half a cell of ``QUANTUM``.
#: Why: a Gaussian narrower than half a cell puts (almost) all its mass on one cell, i.e. it claims
#: to know in which cell the object will be. Maximum likelihood reaches that claim whenever every
#: such frame of the calibration clips lands in its predicted cell (returns after hidden impacts
#: are rare there, and the best of a grid of elasticities fits each calibration bounce after the
#: fact), the continuous version of a zero count; like the Laplace smoothing of ``p_present``, the
#: floor keeps the claim at the resolution of the observation space. It is also the spacing the
#: oracle's elasticity hypotheses are refined to (``voe.models.hypotheses``), so its mixture is
#: never a comb of hypotheses narrower than their gaps. An object's look (``CONSTANT``) is carried
#: unchanged by the world's law and keeps its fit.
RETURN_FLOOR = tuple(0.0 if f in CONSTANT else q / 2 for f, q in zip(CONT, QUANTUM, strict=True))
#: Robust outlier component of every state Gaussian: its weight, and a uniform range per ``CONT``
#: feature (for the angle, the range of the wrapped residual: one full turn).
OUTLIER = 0.01
RANGE = ((-5.0, 15.0), (-5.0, 15.0), (-np.pi, np.pi), (-20.0, 20.0), (-20.0, 20.0), (-40.0, 40.0),
         (0.0, 3.0), (0.0, 3.0), (0.0, 1.5))
LOG2PI = float(np.log(2 * np.pi))
#: Slot kinds of a prediction: tracked (present last frame), returning (seen before, absent last
#: frame) and new (never seen).
TRACKED, RETURNING, NEW = 0, 1, 2


def cont_index(feature_names: tuple[str, ...]) -> list[int]:
    """Indices of ``CONT`` (and ``is_circle``) in a batch's features, with a clear error."""
    missing = [f for f in (*CONT, "is_circle") if f not in feature_names]
    if missing:
        raise ModelContractError(f"state models need features {missing}, batch has {list(feature_names)}")
    return [feature_names.index(f) for f in CONT]


def carry(states: np.ndarray, present: np.ndarray, dt: float,
          step: Callable[[np.ndarray, float], np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-slot memory: the state at t if present, else the carried prediction.

    Args:
        states: ``(B, T, K, F)`` with NaN where absent.
        present: ``(B, T, K)``.
        step: advances ``(N, F)`` states by one frame.

    Returns:
        mem ``(B, T, K, F)`` (NaN for never-seen slots), known ``(B, T, K)`` (seen at or before t),
        age ``(B, T, K)`` frames since last seen (0 when present).
    """
    B, T, K, F = states.shape
    mem = np.full_like(states, np.nan)
    known = np.zeros((B, T, K), dtype=bool)
    age = np.zeros((B, T, K), dtype=np.float32)
    cur = np.full((B, K, F), np.nan, dtype=states.dtype)
    seen = np.zeros((B, K), dtype=bool)
    a = np.zeros((B, K), dtype=np.float32)
    for t in range(T):
        if t > 0 and seen.any():
            cur[seen] = step(cur[seen], dt)
        p = present[:, t]
        cur[p] = states[:, t][p]
        seen |= p
        a = np.where(p, 0.0, a + seen)
        mem[:, t], known[:, t], age[:, t] = cur, seen, a
    return mem, known, age


def constant_velocity_step(s: np.ndarray, dt: float, names: tuple[str, ...]) -> np.ndarray:
    """Advance ``(N, F)`` states one frame at constant velocity."""
    out = s.copy()
    for p, v in (("x", "vx"), ("y", "vy"), ("angle", "omega")):
        out[:, names.index(p)] += dt * s[:, names.index(v)]
    return out


def slot_kind(known: np.ndarray, present: np.ndarray) -> np.ndarray:
    """Kind of the prediction for frame t (t >= 1) from memory at t-1: ``(B, T, K)`` int."""
    kind = np.full(known.shape, NEW, dtype=np.int8)
    kind[:, 1:][known[:, :-1]] = RETURNING
    kind[:, 1:][present[:, :-1]] = TRACKED
    return kind


@dataclass(frozen=True)
class Noise:
    """Calibrated noise of a point predictor (all fitted by maximum likelihood).

    Attributes:
        sigma: per ``CONT`` feature, for tracked slots.
        sigma_return: per ``CONT`` feature, for slots reappearing after being absent.
        sigma_contact: per ``CONT`` feature, for tracked slots the predictor marks as in an impact
            (only predictors that know when contacts happen, such as the physics oracle, mark any).
        prior_mean, prior_sigma: per ``CONT`` feature, for slots never seen before.
        p_present: P(present) for tracked, returning and new slots.
        p_circle: P(circle) of a new object; p_keep: P(shape unchanged) of a known one.
    """

    sigma: tuple[float, ...] = (0.05, 0.05, 0.1, 0.3, 0.4, 0.3, 1e-3, 1e-3, 1e-3)
    sigma_return: tuple[float, ...] = (0.5, 0.5, 1.0, 1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3)
    sigma_contact: tuple[float, ...] = (0.05, 0.05, 0.1, 0.5, 0.5, 0.5, 1e-3, 1e-3, 1e-3)
    prior_mean: tuple[float, ...] = (5.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.9, 0.9, 0.8)
    prior_sigma: tuple[float, ...] = (4.0, 3.0, 1.0, 2.0, 2.0, 2.0, 0.3, 0.3, 0.15)
    p_present: tuple[float, float, float] = (0.98, 0.1, 0.01)
    p_circle: float = 0.5
    p_keep: float = 0.999


def _wrap(d: np.ndarray) -> np.ndarray:
    return (d + np.pi) % (2 * np.pi) - np.pi


def residuals(obs: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """``obs - mean`` over ``CONT`` with the angle wrapped; ``(..., 9)``."""
    r = obs - mean
    r[..., 2] = _wrap(r[..., 2])
    return r


def gaussian_nll(r: np.ndarray, sigma: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """Summed over the last axis: ``-log P(cell)`` of observation ``obs`` (residual ``r``) under
    ``(1 - OUTLIER) N(mu, sigma^2) + OUTLIER Uniform(RANGE)``, per feature.

    Why the mixture: one confidently mispredicted contact would otherwise cost thousands of
    nats and dominate every average; the uniform component caps a wrong feature at about
    ``log(1 / OUTLIER) + log(range / cell)`` nats (12 to 13).
    """
    return -cell_logp(r, sigma, obs).sum(-1)


def uniform_logp(r: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """Per feature ``log P(cell)`` under ``Uniform(RANGE)`` (-1e4 outside the range)."""
    lo, hi = np.asarray(RANGE).T
    v = np.concatenate([obs[..., :2], r[..., 2:3], obs[..., 3:]], -1)  # angle: its residual
    inside = (v >= lo) & (v <= hi)
    return np.where(inside, np.log(np.asarray(QUANTUM) / (hi - lo)), -1e4)


def cell_logp(r: np.ndarray, sigma: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """Per feature ``log P(cell)`` under the robust mixture (see ``gaussian_nll``)."""
    narrow = _cell_logp(r, np.broadcast_to(sigma, r.shape))
    return np.minimum(np.logaddexp(np.log1p(-OUTLIER) + narrow, np.log(OUTLIER) + uniform_logp(r, obs)), 0.0)


def _cell_logp(r: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """``log P(cell)`` per feature, cell ``r +- QUANTUM / 2`` under ``N(0, sigma^2)``; log-CDFs
    keep far tails finite, density times width is used where the cell is tiny against sigma."""
    from scipy.special import log_ndtr

    q = np.asarray(QUANTUM)
    lo, hi = (r - q / 2) / sigma, (r + q / 2) / sigma
    flip = lo > 0  # use the lower tail, where log_ndtr is accurate
    lo, hi = np.where(flip, -hi, lo), np.where(flip, -lo, hi)
    lh, ll = log_ndtr(hi), log_ndtr(lo)
    d = np.minimum(ll - lh, 0.0)
    with np.errstate(divide="ignore"):
        exact = lh + np.log(-np.expm1(d))
    dens = -(0.5 * (r / sigma) ** 2 + np.log(sigma) + 0.5 * LOG2PI) + np.log(q)
    return np.minimum(np.where(d > -1e-6, dens, exact), 0.0)


def score(batch: Batch, mean: np.ndarray, kind: np.ndarray, noise: Noise,
          p_present: np.ndarray | None = None, circle_mem: np.ndarray | None = None,
          contact: np.ndarray | None = None, shape_prior: np.ndarray | None = None,
          per_slot: bool = False) -> np.ndarray:
    """Per-frame surprise ``(B, T)`` (frame 0 NaN) of a point prediction with calibrated noise.

    Args:
        mean: ``(B, T, K, 9)`` predicted ``CONT`` for frame t (ignored for new slots).
        kind: ``(B, T, K)`` from ``slot_kind``.
        p_present: optional ``(B, T, K)`` override of P(present) (the oracle knows the screens).
        circle_mem: ``(B, T, K)`` remembered is_circle for known slots.
        contact: optional ``(B, T, K)`` bool, tracked slots predicted through an impact (scored
            with ``noise.sigma_contact``).
        shape_prior: optional ``(B, T, K)`` bool, known slots whose shape and size are scored
            like a new object's (a model that does not remember them).
        per_slot: return each slot's share, ``(B, T, K)``, instead of the frame's sum.
    """
    idx = cont_index(batch.feature_names)
    obs = batch.states[..., idx].astype(np.float64)  # (B, T, K, 9)
    pres = batch.present
    new = kind == NEW
    fresh_look = new if shape_prior is None else new | shape_prior
    mu = np.where(new[..., None] | (fresh_look[..., None] & _SHAPE), np.asarray(noise.prior_mean), mean)
    tracked = kind == TRACKED
    hit = tracked & contact if contact is not None else np.zeros_like(tracked)
    sig = np.select([hit[..., None], tracked[..., None], (kind == RETURNING)[..., None]],
                    [np.asarray(noise.sigma_contact), np.asarray(noise.sigma), np.asarray(noise.sigma_return)],
                    np.asarray(noise.prior_sigma))
    sig = np.where(fresh_look[..., None] & _SHAPE, np.asarray(noise.prior_sigma), sig)
    pp = np.asarray(noise.p_present)[kind] if p_present is None else p_present
    pp = np.clip(pp, 1e-6, 1 - 1e-6)
    nll = -np.where(pres, np.log(pp), np.log1p(-pp))  # (B, T, K)
    obs0 = np.nan_to_num(obs)
    cont = gaussian_nll(residuals(obs0, np.nan_to_num(mu)), sig, obs0)
    circ = batch.states[..., batch.feature("is_circle")] > 0.5
    if circle_mem is None:
        circle_mem = np.zeros_like(circ)
    p_shape = np.where(fresh_look, np.where(circ, noise.p_circle, 1 - noise.p_circle),
                       np.where(circ == circle_mem, noise.p_keep, 1 - noise.p_keep))
    nll = nll + np.where(pres, cont - np.log(np.clip(p_shape, 1e-9, 1)), 0.0)
    out = nll if per_slot else nll.sum(-1)  # (B, T, K) or (B, T)
    out[:, 0] = np.nan
    return out


def robust_sigma(r: np.ndarray, iters: int = 50, floor: float = 1e-3) -> np.ndarray:
    """Maximum-likelihood sigma per ``CONT`` feature under the robust mixture, by EM.

    Why not the RMS: the likelihood is ``(1 - OUTLIER) N(0, sigma^2) + OUTLIER Uniform(RANGE)``,
    and its maximum-likelihood sigma ignores what the uniform component explains. The RMS lets a
    few mispredicted contacts set sigma for every frame, so a well-predicted object would cost
    several nats per frame merely for being in view, and clips that show objects for longer would
    look more surprising whatever happens in them.

    Args:
        r: ``(N, 9)`` residuals.

    Returns:
        ``(9,)`` sigmas, at least ``floor``.
    """
    lo, hi = np.asarray(RANGE).T
    u = OUTLIER / (hi - lo)  # (9,) outlier density
    sig = np.maximum(np.sqrt((r ** 2).mean(0)), floor)
    for _ in range(iters):
        g = (1 - OUTLIER) * np.exp(-0.5 * (r / sig) ** 2) / (sig * np.sqrt(2 * np.pi))  # (N, 9)
        resp = g / (g + u)
        new = np.maximum(np.sqrt((resp * r ** 2).sum(0) / np.maximum(resp.sum(0), 1e-12)), floor)
        if np.allclose(new, sig, rtol=1e-4):
            break
        sig = new
    return sig


def fit_noise(batch: Batch, mean: np.ndarray, kind: np.ndarray, circle_mem: np.ndarray,
              contact: np.ndarray | None = None) -> Noise:
    """Maximum-likelihood noise for a point predictor on (possible) clips ``batch``."""
    idx = cont_index(batch.feature_names)
    obs = batch.states[..., idx].astype(np.float64)
    pres = batch.present.copy()
    pres[:, 0] = False  # frame 0 is not scored
    d = Noise()

    def rms(sel: np.ndarray, default: tuple[float, ...], ref: np.ndarray, robust: bool = True) -> tuple[float, ...]:
        if sel.sum() < 5:
            return default
        r = residuals(obs[sel], ref[sel])
        if not robust:  # the spread of a population (new objects), not a predictor's error
            return tuple(float(v) for v in np.maximum(np.sqrt((r ** 2).mean(0)), 1e-3))
        return tuple(float(v) for v in robust_sigma(r))

    tracked, ret, new = (pres & (kind == k) for k in (TRACKED, RETURNING, NEW))
    hit = tracked & contact if contact is not None else np.zeros_like(tracked)
    prior_mean = tuple(float(v) for v in obs[new].mean(0)) if new.sum() >= 5 else d.prior_mean
    pm = np.broadcast_to(np.asarray(prior_mean), obs.shape)
    p_present = []
    for k in (TRACKED, RETURNING, NEW):
        sel = kind[:, 1:] == k
        n_pres = batch.present[:, 1:][sel].sum()
        p_present.append(float((n_pres + 1) / (sel.sum() + 2)))  # Laplace smoothing
    circ = batch.states[..., batch.feature("is_circle")] > 0.5
    known = pres & (kind != NEW)
    keep = float((np.sum(circ[known] == circle_mem[known]) + 1) / (known.sum() + 2))
    def floored(sig: tuple[float, ...]) -> tuple[float, ...]:
        return tuple(max(v, f) for v, f in zip(sig, RETURN_FLOOR, strict=True))

    return Noise(sigma=rms(tracked & ~hit, d.sigma, mean), sigma_return=floored(rms(ret, d.sigma_return, mean)),
                 sigma_contact=floored(rms(hit, d.sigma_contact, mean)),
                 prior_mean=prior_mean, prior_sigma=rms(new, d.prior_sigma, pm, robust=False),
                 p_present=tuple(p_present),
                 p_circle=float((circ[new].sum() + 1) / (new.sum() + 2)), p_keep=keep)
