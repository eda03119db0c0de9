"""Timing jitter: samples taken off their time stamps, estimated from the recordings and
reproduced in every clean replicate.

Why: a sample taken dt late records a body where it is dt later, an error of v dt that grows
with the body's speed, while the noise model (``voe.gap.shooting.noise_model``) is one sigma per
body and variable, from robust (median) fourth differences that the slow samples dominate. Clean
replicates with that noise are too quiet where the bodies move fast and too loud where they rest,
so the data's fast windows stand out against them whatever the physics. Development seeds 6685 and
1078: of 40 clean cases with the bench's timestamp jitter (2 ms, clipped at 4 ms), 14 were located
with departure p < 0.01 (``unexplained``) and 20 had p < 0.01; with white or coloured noise 0 of 216.

The fourth difference of samples taken at equal steps removes smooth motion and leaves the noise:
``70 sigma^2`` for white sensor noise (``voe.gap.shooting.d4_var`` for AR(1)), plus ``jitter^2 * sum_i c_i^2
v_i^2`` (c = 1, -4, 6, -4, 1) for independent sampling-time errors of standard deviation
``jitter``, where v_i is the speed at each of the five samples. Per body and variable, the samples
are put into bins by that speed term, each bin's variance is estimated robustly (median of the
squared fourth differences, so impacts do not count), and the bins of all bodies and variables are
fitted with one sensor variance per body and variable and one jitter shared by all (one clock
takes every body's sample). The jitter is used only when it is clear: the fit's relative misfit
must fall by ``CLEAR`` times. Development seeds 6685, 1078, 1967, 2250 (``docs/bench-runs/dev-s29``):
it opened on none of 483 white or coloured cases (singles, floor patches, gusts, clean) and 20 with
dropouts, nor on the real single pendulum, and on all 40 jittered ones, at 1.7-2.1 ms (0.5 ms
jitter: 0.45-0.58 ms). A prototype's unconstrained fit on 101 of them: the misfit fell at most
1.36 times without jitter, 6.3-21 times with the bench's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from voe.gap.recordings import Episode
from voe.gap.shooting import d4_var

CLEAR = 2.0  # the jitter model must cut the binned fit's relative misfit by this factor to be used
BINS = 8  # speed bins per body and variable
MIN_BIN = 20  # samples per bin
SPEED_HALF = 3  # speed from a central difference over +-3 samples: its noise is sigma / (3 dt sqrt 2)
_C2 = np.array([1.0, 16.0, 36.0, 16.0, 1.0])  # squared coefficients of the fourth difference
_MEDIAN_CHI2 = 0.45494  # median of a chi-square variable with one degree of freedom


@dataclass(frozen=True)
class Jitter:
    """Sampling-time errors of ``seconds`` (standard deviation, one per sample, shared by all
    bodies), on top of position noise of ``sensor`` (B, 3), the noise floor without them."""

    seconds: float
    sensor: np.ndarray  # (B, 3)


def timing_jitter(episodes: list[Episode], phi: np.ndarray) -> Jitter | None:
    """The recordings' timing jitter and the sensor noise beneath it, or None when the data do
    not show it clearly (see the module docstring). ``phi`` (B, 3) is the noise model's AR(1)
    coefficient, which sets the sensor's fourth-difference variance."""
    d4s, us = [], []
    for e in episodes:
        d4, u = _terms(e)
        d4s.append(d4)
        us.append(u)
    if sum(len(d) for d in d4s) < BINS * MIN_BIN:  # also no episodes at all
        return None
    d4, u = np.concatenate(d4s), np.concatenate(us)  # (N, B, 3) each
    n_bc = d4.shape[1] * 3
    rows, y = [], []
    for b, k in np.ndindex(d4.shape[1], 3):
        edges = np.quantile(u[:, b, k], np.linspace(0, 1, BINS + 1))
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            m = (u[:, b, k] >= lo) & (u[:, b, k] <= hi)
            var = np.median(d4[m, b, k] ** 2) / _MEDIAN_CHI2 if m.sum() >= MIN_BIN else 0.0
            if var > 0:
                row = np.zeros(n_bc + 1)
                row[b * 3 + k], row[-1] = 1.0, np.median(u[m, b, k])
                rows.append(row)
                y.append(var)
    if len(y) <= n_bc + 1:
        return None
    a, y = np.array(rows) / np.array(y)[:, None], np.ones(len(y))  # relative errors
    with_j, res1 = nnls(a, y)
    _, res0 = nnls(a[:, :-1], y)
    if with_j[-1] <= 0 or res0**2 < CLEAR * max(res1**2, 1e-12):
        return None
    sensor = np.sqrt(np.maximum(with_j[:-1].reshape(-1, 3), 0.0) / d4_var(phi))  # (B, 3)
    return Jitter(float(np.sqrt(with_j[-1])), np.maximum(sensor, 1e-7))


def _terms(e: Episode) -> tuple[np.ndarray, np.ndarray]:
    """(N, B, 3) fourth differences of ``e`` over five equally spaced samples, and (N, B, 3) the
    speed term ``sum_i c_i^2 v_i^2`` of the same samples (the jitter's variance per jitter^2)."""
    t, pose = e.t, e.pose
    h = SPEED_HALF
    if len(t) < 2 * h + 5:
        return np.zeros((0,) + pose.shape[1:]), np.zeros((0,) + pose.shape[1:])
    dt = np.diff(t)
    step = np.median(dt)
    v = np.full(pose.shape, np.nan)
    v[h:-h] = (pose[2 * h:] - pose[:-2 * h]) / (t[2 * h:] - t[:-2 * h])[:, None, None]  # (T, B, 3)
    even = np.abs(dt / step - 1.0) < 0.01  # (T-1,) a gap (dropout) breaks the difference
    ok = np.lib.stride_tricks.sliding_window_view(even, 4).all(axis=1)  # (T-4,)
    u = sum(_C2[i] * v[i:len(v) - 4 + i] ** 2 for i in range(5))  # (T-4, B, 3)
    ok &= np.isfinite(u).all(axis=(1, 2))
    return np.diff(pose, n=4, axis=0)[ok], u[ok]


def jitter_noise(clean: np.ndarray, t: np.ndarray, seconds: float, rng: np.random.Generator) -> np.ndarray:
    """(T, B, 3) the error of taking each sample of ``clean`` (T, B, 3) at ``t`` (T,) off by a
    normal draw of ``seconds``: velocity times the time error (one draw per sample, all bodies)."""
    v = np.gradient(clean, t, axis=0)  # (T, B, 3)
    return v * rng.normal(0.0, seconds, len(t))[:, None, None]
