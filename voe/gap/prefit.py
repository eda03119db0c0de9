"""Starting points for force effects from the accelerations seen in free flight.

Why: a force effect with a position parameter (a point attractor, a spring anchor) has a
multiple-shooting cost full of local minima: started far from the point, the search settles on
"a far-away attractor", which is a constant acceleration. In free flight the nominal model
predicts the acceleration exactly (gravity), so what the recordings show beyond gravity *is* the
missing force per unit mass, sampled at known positions and velocities. Fitting an effect's force
law to those samples is a cheap regression (no simulation), and its result is a starting point
near the answer for the simulator fit, which alone decides. Samples come from a Savitzky-Golay
fit of each flight stretch; bodies on joints or in contact are left out, because there the
nominal acceleration is not known without simulating. Contact includes touching another body
(``voe.gap.context.near_bodies``): on development case 3629012 (a spring to an anchor) half of
the "flight" samples were the ball resting on the box, recorded acceleration zero, read as
+9.8 m/s^2 missing; the regression start put the anchor at the edge of its bounds with k 2.4
times too large, the simulator fit went to k = 0 and the case ended ``unexplained``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.signal import savgol_coeffs, savgol_filter

from voe.gap.context import frame_labels, near_bodies
from voe.gap.effects.base import Effect, EffectSum
from voe.gap.recordings import Episode
from voe.sim.scenefile import SceneSpec, SimState

HALF = 12  # samples each side of the Savitzky-Golay fit (0.25 s at 100 Hz)
# A short span for forces that change within a fraction of a second (``Effect.fine_flight``):
# a body passing 0.3 m from an attractor feels its pull rise and fall within about 0.1 s, and a
# 0.25 s cubic smooths that peak away, so the regression puts the point too far off and makes it
# too strong. Development seed 7857 (fitting episodes of 7857047, true point (-0.68, 1.26) m,
# k = 0.98): half 12 gives (-0.58, 1.80) m at k = 1.12, half 5 (-0.70, 1.26) m at k = 0.68;
# 7857008 (true (-0.86, 0.82) m): (-1.09, 1.69) m against (-0.86, 0.83) m. The noise it lets
# through is what the regression's soft-L1 loss is for.
FINE_HALF = 5  # 0.05 s at 100 Hz
MIN_SAMPLES = 30
MAX_SAMPLES = 3000  # a regression start needs no more; keeps the multi-start cheap


@dataclass(frozen=True)
class FlightSamples:
    """Free-flight samples of all bodies: state and the acceleration beyond gravity.

    Attributes:
        state: stacked states, one row per sample (N rows in place of B bodies).
        body: (N,) index of the body each row belongs to.
        dacc: (N, 2) recorded minus nominal linear acceleration, m/s^2.
        dalpha: (N,) recorded minus nominal angular acceleration, rad/s^2.
        gyration: (N,) sqrt(I/m) of the row's body (turns angular terms into metres).
        time: (N,) the sample's time since its episode began, s; episode: (N,) its episode's
            place in the list (``voe.gap.drift`` asks whether what is missing changes in time).
        around: the states of the recorded frames whose accelerations the smoothing averages
            into each sample's (K = 2 half - 1 per sample, sample by sample: N * K rows), or
            None; kernel: (K,) their weights (``smoothing_kernel``).
    """

    state: SimState
    body: np.ndarray
    dacc: np.ndarray
    dalpha: np.ndarray
    gyration: np.ndarray
    time: np.ndarray | None = None
    episode: np.ndarray | None = None
    around: SimState | None = None
    kernel: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.body)


def smoothing_kernel(half: int) -> np.ndarray:
    """(2 half - 1,) weights w with which the Savitzky-Golay second derivative (cubic, 2 half + 1
    samples) of a path equals sum_k w_k a_{t+k}, a the path's second differences over dt^2.

    Why: the filter annihilates constants and lines, so its coefficients c are the second
    difference of some w (c_j = w_{j-1} - 2 w_j + w_{j+1}), found by summing c twice; the weights
    sum to 1 (a parabola's second derivative is exact) and do not depend on dt. A recorded flight
    acceleration is this average of the true one over 0.25 s (``HALF``), not its value at the
    sample: near an attracting point, where the pull rises and falls within 0.1 s, the two
    differ by tens of m/s^2 (development case 2758047, true attractor: median 19 m/s^2 within
    0.2 m of the point).
    """
    return np.cumsum(np.cumsum(savgol_coeffs(2 * half + 1, 3, deriv=2, use="dot")))[:-2]


def flight_samples(scene: SceneSpec, episodes: list[Episode], half: int = HALF,
                   rng: np.random.Generator | None = None, around: bool = False) -> FlightSamples | None:
    """Collect free-flight samples whose whole fitting span is in flight; None if too few.

    ``around``: also keep, for each sample, the frames its smoothed acceleration averages
    (``FlightSamples.around``; recorded positions and angles, smoothed velocities), so that an
    effect's acceleration can be smoothed as the recording was (``seen_missing``). The samples
    are the same with or without.
    """
    jointed = scene.jointed()
    g = np.asarray(scene.gravity, dtype=float)
    rows: dict[str, list] = {k: [] for k in ("pos", "vel", "ang", "om", "acc", "alpha", "body", "t", "ep")}
    near_rows: dict[str, list] = {k: [] for k in ("pos", "vel", "ang", "om")}  # each (n, K, ...)
    offs = np.arange(-half + 1, half)  # (K,) the frames ``smoothing_kernel`` weighs
    for i_ep, ep in enumerate(episodes):
        t_len = len(ep.t)
        if t_len < 2 * half + 1:
            continue
        dt = float(np.median(np.diff(ep.t)))
        labels = frame_labels(scene, ep)  # (T, B)
        near = near_bodies(scene, ep)  # (T, B): resting on or touching another body is no flight
        kw = {"window_length": 2 * half + 1, "polyorder": 3, "axis": 0, "delta": dt, "mode": "interp"}
        pose = savgol_filter(ep.pose, deriv=0, **kw)  # (T, B, 3)
        vel = savgol_filter(ep.pose, deriv=1, **kw)
        acc = savgol_filter(ep.pose, deriv=2, **kw)
        for b in range(ep.pose.shape[1]):
            if jointed[b]:
                continue
            fl = ((labels[:, b] == "flight") & ~near[:, b]).astype(float)
            ok = np.convolve(fl, np.ones(2 * half + 1), mode="same") >= 2 * half + 1  # whole span in flight
            ok[:half] = ok[t_len - half:] = False
            k = np.flatnonzero(ok)
            rows["pos"].append(pose[k, b, :2])
            rows["vel"].append(vel[k, b, :2])
            rows["ang"].append(pose[k, b, 2])
            rows["om"].append(vel[k, b, 2])
            rows["acc"].append(acc[k, b, :2] - g)
            rows["alpha"].append(acc[k, b, 2])
            rows["body"].append(np.full(len(k), b))
            rows["t"].append(ep.t[k] - ep.t[0])
            rows["ep"].append(np.full(len(k), i_ep))
            if around:  # frames k - half + 1 .. k + half - 1, all in flight (the whole span is)
                kk = k[:, None] + offs[None, :]  # (n, K)
                near_rows["pos"].append(ep.pose[kk, b, :2])
                near_rows["ang"].append(ep.pose[kk, b, 2])
                near_rows["vel"].append(vel[kk, b, :2])
                near_rows["om"].append(vel[kk, b, 2])
    if not rows["body"] or sum(len(b) for b in rows["body"]) < MIN_SAMPLES:
        return None
    cat = {k: np.concatenate(v) for k, v in rows.items()}
    near = {k: np.concatenate(v) for k, v in near_rows.items()} if around else {}
    n = len(cat["body"])
    if n > MAX_SAMPLES:
        pick = np.sort((rng or np.random.default_rng(0)).choice(n, MAX_SAMPLES, replace=False))
        cat = {k: v[pick] for k, v in cat.items()}
        near = {k: v[pick] for k, v in near.items()}
    body = cat["body"]
    mass = np.array([b.mass for b in scene.bodies])[body]
    moment = np.array([b.moment_value() for b in scene.bodies])[body]
    gyr = np.array([b.gyration_radius for b in scene.bodies])[body]
    no_contact = np.zeros(len(body), dtype=bool)
    state = SimState(cat["pos"], cat["vel"], cat["ang"], cat["om"], mass, moment, g, lambda: no_contact)
    if not around:
        return FlightSamples(state, body, cat["acc"], cat["alpha"], gyr, cat["t"], cat["ep"])
    n_k = len(offs)
    no_contact_k = np.zeros(len(body) * n_k, dtype=bool)
    near_state = SimState(near["pos"].reshape(-1, 2), near["vel"].reshape(-1, 2), near["ang"].reshape(-1),
                          near["om"].reshape(-1), np.repeat(mass, n_k), np.repeat(moment, n_k), g,
                          lambda: no_contact_k)  # (N * K) rows, sample by sample
    return FlightSamples(state, body, cat["acc"], cat["alpha"], gyr, cat["t"], cat["ep"], near_state,
                         smoothing_kernel(half))


def _missing(effect: Effect, params: np.ndarray, s: FlightSamples, scene: SceneSpec) -> tuple[np.ndarray, np.ndarray]:
    """Acceleration (N, 2) and angular acceleration (N,) that ``effect`` adds at the samples."""
    parts = effect.parts
    split = effect.split(params) if isinstance(effect, EffectSum) else [params]
    acc, alpha = np.zeros_like(s.dacc), np.zeros_like(s.dalpha)
    for e, p in zip(parts, split, strict=True):
        if not e.has_forces or not e.flight_regression:  # contact, region and joint terms: nothing in flight
            continue
        f, tau = e._forces(s.state, e.check(p))
        m = e.mask(scene)[s.body]  # (N,)
        acc += f * (m / s.state.mass)[:, None]
        alpha += tau * m / s.state.moment
    return acc, alpha


def seen_missing(effect: Effect, params: np.ndarray, s: FlightSamples,
                 scene: SceneSpec) -> tuple[np.ndarray, np.ndarray]:
    """``_missing`` as the recording shows it: averaged over the frames around each sample with
    the smoothing's own weights (``smoothing_kernel``); ``_missing`` itself if the samples keep no
    frames around. Why: a residual against the unsmoothed value is the smoothing's bias wherever
    the force changes within the span, a bias that lies where the bodies pass, so at the times
    they pass (``voe.gap.drift_flight.flight_drift``)."""
    if s.around is None or s.kernel is None:
        return _missing(effect, params, s, scene)
    n, n_k = len(s), len(s.kernel)
    rows = FlightSamples(s.around, np.repeat(s.body, n_k), np.zeros((n * n_k, 2)), np.zeros(n * n_k),
                         np.repeat(s.gyration, n_k))
    acc, alpha = _missing(effect, params, rows, scene)  # (N * K, 2), (N * K,)
    return (np.einsum("nkd,k->nd", acc.reshape(n, n_k, 2), s.kernel),
            alpha.reshape(n, n_k) @ s.kernel)


def prefit_starts(cand: Effect, starts: list[np.ndarray], lo: np.ndarray, hi: np.ndarray, scale: np.ndarray,
                  samples: FlightSamples | None, scene: SceneSpec, current: Effect | None = None,
                  current_params: np.ndarray | None = None, keep: int = 2) -> list[np.ndarray]:
    """The ``keep`` best distinct regression fits of ``cand`` to the flight accelerations left
    unexplained by ``current``, each started from one of ``starts``; [] if not applicable."""
    if samples is None or not cand.has_forces or not cand.flight_regression or len(samples) < MIN_SAMPLES:
        return []
    dacc, dalpha = samples.dacc, samples.dalpha
    if current is not None and current_params is not None and current_params.size:
        a0, al0 = _missing(current, current_params, samples, scene)
        dacc, dalpha = dacc - a0, dalpha - al0
    # robust scale of the acceleration noise, so the soft-L1 knee sits at a few noise sigmas
    noise = 1.4826 * np.median(np.abs(dacc - np.median(dacc, axis=0)))
    gyr = samples.gyration

    def resid(p: np.ndarray) -> np.ndarray:
        a, al = _missing(cand, p, samples, scene)
        return np.concatenate([(a - dacc).reshape(-1), (al - dalpha) * gyr])

    lo_f = np.where(np.isfinite(lo), lo, -1e6)
    hi_f = np.where(np.isfinite(hi), hi, 1e6)
    fits = []
    for s in starts:
        x0 = np.clip(s, lo_f, hi_f)
        x0 = np.where(x0 <= lo_f, lo_f + 1e-9 * np.maximum(1, np.abs(lo_f)), x0)
        x0 = np.where(x0 >= hi_f, hi_f - 1e-9 * np.maximum(1, np.abs(hi_f)), x0)
        try:
            r = least_squares(resid, x0, bounds=(lo_f, hi_f), x_scale=scale, loss="soft_l1",
                              f_scale=max(3 * noise, 1e-3), max_nfev=60)
        except ValueError:
            continue
        if np.all(np.isfinite(r.x)) and np.isfinite(r.cost):
            fits.append((float(r.cost), r.x))
    fits.sort(key=lambda c: c[0])
    out: list[np.ndarray] = []
    for _, x in fits:
        if all(np.any(np.abs(x - y) > 0.1 * scale) for y in out):
            out.append(x)
        if len(out) >= keep:
            break
    return out
