"""Does what a model leaves unexplained in free flight change in time? t-tests on the flight residual.

Why a module of its own: the window test (``voe.gap.drift``) compares a model's parameters fitted
at one time with those fitted at others; this one compares the acceleration the model leaves in
free flight, where the nominal acceleration (gravity) is known exactly, one residual per episode and
time slot (``flight_drift``). It is how a constant fitted to a gust or a floor patch is mostly
caught. ``voe.gap.drift.drift_found`` runs both; the verdict and thresholds they share are in
``voe.gap.drift_base``.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares

from voe.gap.drift_base import MATERIAL, Drift, critical
from voe.gap.effects.base import Effect, EffectSum, FitContext
from voe.gap.prefit import FlightSamples, _missing, seen_missing
from voe.sim.scenefile import SceneSpec

FLIGHT_SLOT = 0.25  # s of episode time
OUTLIER = 10.0  # robust sds from the median: a unit this far off holds a touch labelled flight
#: Samples an episode's slot needs to count as a unit of ``flight_drift``: three, the fewest whose
#: median withstands one sample far off (next to an unlabelled touch). Each sample is already a
#: 0.25 s average (``voe.gap.prefit.HALF``), so more samples of one stretch add little.
MIN_UNIT = 3
#: Fewest units on each side of a contrast of ``flight_contrasts``. A slot against the rest needs
#: three (Welch's t on fewer has one degree of freedom). A before/after split pools the variance,
#: so two units on one side are enough: session 56 found gusts (5025141, 1066143) whose late swing
#: was flown only by the last slot's two units.
SLOT_SIDE = 3
SPLIT_SIDE = 2
#: A contrast with a side of fewer than ``SLOT_SIDE`` units must differ by this multiple of the
#: material floor. Why: such a side is two stretches, often short ones that end at a touch, whose
#: smoothed residual carries a bias the pooled spread of the other units does not show; development
#: case 9260067 (a true ``constant_acceleration``) lost its truth to two such units of 4 samples,
#: 0.12 m/s^2 off in y, 1.1 times the floor (t = 3.4). A gust's swing is the floor's size several
#: times over.
SHORT_SIDE_FLOOR = 2.0


def flight_drift(samples: FlightSamples | None, effect: Effect, params: np.ndarray, scene: SceneSpec,
                 ctx: FitContext) -> Drift | None:
    """Does the acceleration left over in free flight, after ``effect`` at ``params``, change with
    episode time? On one value per episode and slot (samples of one stretch are smoothed together,
    so an episode's slot is one unit), per axis: a Welch t-test of each ``FLIGHT_SLOT`` slot's
    residual against all others, and a pooled-variance t-test of the units before each slot
    boundary against those after it (``flight_contrasts``), family-wise ``ALPHA`` over contrasts
    and axes.

    Why the before/after contrasts (session 55): a gust swings over a second or more, so the
    residual a library effect leaves is of one sign for several slots and of the other after;
    one slot against the rest halves that difference and, with three units on its side, a
    Welch test has about two degrees of freedom. Untouched case 9260143 (a gust named
    ``spring_anchor``) left units of 0.03 to 0.33 m/s^2 in the ten before 0.5 s and -0.73, -1.02
    and -1.48 after, in two slots of one and two units: the late swing was in no slot tested; before
    against after, t = 9.5 on 11 degrees of freedom. The variance is pooled because a side of three units cannot
    estimate its own (Welch's t there needs t > 8.8 at this family-wise level); a side usually
    spans two slots or more, so the spread pooled is that of units at several times (a side may be
    two units since session 57, ``SPLIT_SIDE``). Counted on the gusts
    of twenty development seeds (120), each library effect that pushes in flight fitted in flight
    (600 pairs): caught in 537 against 493 with the slot tests alone (4 lost to the larger family),
    every library effect caught in 94 gusts against 85; the truth of 500 single-effect and 60
    compound cases at its true parameters drifted in none, with or without (docs/gap-findings.md,
    session 55).

    A significant change must also be *material*: at least ``MATERIAL`` of the median missing
    acceleration in flight (``|dacc|``, what the effect has to explain). Why: with hundreds of
    flight samples a few hundredths of a m/s^2 are significant; untouched bench case 7741009 lost
    a right ``quadratic_drag`` (selection gain 88 %, about 1 m/s^2 in flight) to a residual that
    was -0.029 m/s^2 in one slot and 0.011 elsewhere (t = 3.7), the drag's small misfit changing
    with the speed, and 7741041 a right ``constant_acceleration`` (gain 84 %, 0.57 m/s^2) to
    -0.033 against 0.036 m/s^2 (t = 3.3). A gust fitted by a constant leaves a swing of the
    gust's own size, about the median missing acceleration or more. A contrast with a side of
    two units must differ by twice that (``SHORT_SIDE_FLOOR``).

    Why in flight: there the nominal acceleration is known exactly (gravity), so what is left is
    the missing force per unit mass at a known time (``voe.gap.prefit``); a constant acceleration
    fitted to a gust leaves the gust's swing, the same at the same time in every episode. The
    effect's parameters are first refitted to the flight samples (``_flight_fit``): flight pins a
    force down so tightly that the simulator fit's own small offset shows (a true linear drag
    fitted 3 % off left 0.06 m/s^2 that changed with the speed, so with time, at t = 5.6).

    ``samples`` should keep the frames around each sample (``flight_samples(..., around=True)``):
    the effect's acceleration is then averaged over them as the recording's smoothing averaged
    the true one (``voe.gap.prefit.seen_missing``). Why: development case 2758047, a true point
    attractor, was dropped at t = 4.2 (x: -3.5 m/s^2 in the slot at 0.75 s against 1.2
    elsewhere) at its true parameters too. Its pull rises and falls within 0.1 s as a body
    passes the point, and the 0.25 s smoothing spreads it: within 0.2 m of the point the
    unsmoothed residual was 19 m/s^2 (median), and the bodies pass there at some times of the
    episodes, not others. Smoothed alike, 0.17 m/s^2, the noise's size; a constant or a drag,
    nearly constant over 0.25 s, is unchanged.
    """
    if samples is None or samples.time is None or len(samples) < 30:
        return None
    params = _flight_fit(samples, effect, params, scene, ctx)
    acc, _ = seen_missing(effect, params, samples, scene)
    res = samples.dacc - acc  # (N, 2)
    got = flight_units(samples, res)
    if got is None:
        return None
    u, lab = got  # (U, 2), (U,)
    floor = MATERIAL * float(np.median(np.linalg.norm(samples.dacc, axis=1)))  # m/s^2
    tests = [(name, mask, j) for name, mask in flight_contrasts(lab) for j in range(2)]
    worst = None
    for name, mask, j in tests:
        x, y = u[mask, j], u[~mask, j]
        z, df = _t_pooled(x, y) if name.startswith("before") else _t_welch(x, y)
        short = min(len(x), len(y)) < SLOT_SIDE
        material = abs(x.mean() - y.mean()) >= floor * (SHORT_SIDE_FLOOR if short else 1.0)
        if material and z > critical(df, len(tests)) and (worst is None or z > worst.z):
            worst = Drift(-1, "xy"[j], name, float(x.mean()), float(y.mean()), float(z), True)
    return worst


def flight_units(samples: FlightSamples, res: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The units ``flight_drift`` tests: per episode and ``FLIGHT_SLOT`` slot with at least
    ``MIN_UNIT`` samples, the median of the residual acceleration ``res`` (N, 2), units further
    than ``OUTLIER`` MADs from the median on either axis left out. Returns the (U, 2) units and
    their (U,) slots, or None with fewer than six.

    Why the median and the outlier cut: a sample next to a touch the recording did not label is
    far off, and one such unit would otherwise decide a contrast of a few units.
    """
    slot = np.floor(samples.time / FLIGHT_SLOT).astype(int)  # (N,)
    units, labels = [], []
    for key in sorted(set(zip(samples.episode.tolist(), slot.tolist(), strict=True))):
        m = (samples.episode == key[0]) & (slot == key[1])
        if m.sum() >= MIN_UNIT:
            units.append(np.median(res[m], axis=0))
            labels.append(key[1])
    if len(units) < 6:
        return None
    u = np.array(units)  # (U, 2)
    mad = 1.4826 * np.median(np.abs(u - np.median(u, axis=0)), axis=0)  # (2,)
    keep = np.all(np.abs(u - np.median(u, axis=0)) <= OUTLIER * np.maximum(mad, 1e-9), axis=1)
    if keep.sum() < 6:
        return None
    return u[keep], np.array(labels)[keep]


def flight_contrasts(lab: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """(name, (U,) mask) of the units ``flight_drift`` compares, given each unit's slot ``lab``:
    "time A s", one slot against the rest (each side at least ``SLOT_SIDE`` units), and "before
    A s", the units before a slot boundary against those after it (each side at least
    ``SPLIT_SIDE``); no split twice (the first boundary's is the first slot's, the last's the last
    slot's).

    Since session 57 a before/after side needs two units, not three (``SPLIT_SIDE``), so the late
    side may be the last slot's two units alone; a side usually spans two slots or more.
    Development gusts 5025141 and 1066143 swung late, in the last slot's two units only, and were
    named; with two, 98 of 120 development gusts had every library effect caught against 94. A
    side of two units must also differ by twice the material floor (``SHORT_SIDE_FLOOR``): without
    it the truth at its true parameters drifted in one of 700 singles (9260067), with it in none,
    nor in 60 compounds (one unit a side caught 104 but dropped five true single effects;
    docs/gap-findings.md, sessions 56-57)."""
    slots = np.unique(lab)
    cands = [(f"time {a * FLIGHT_SLOT:.2f} s", lab == a, SLOT_SIDE) for a in slots]
    cands += [(f"before {a * FLIGHT_SLOT:.2f} s", lab < a, SPLIT_SIDE) for a in slots[1:]]
    out: list[tuple[str, np.ndarray]] = []
    for name, m, side in cands:
        if side <= m.sum() <= len(lab) - side and not any(np.array_equal(m, k) or np.array_equal(m, ~k)
                                                          for _, k in out):
            out.append((name, m))
    return out


def _t_welch(x: np.ndarray, y: np.ndarray) -> tuple[float, int]:
    """|t| and Welch-Satterthwaite degrees of freedom (floored) of the difference of two means."""
    vx, vy = x.var(ddof=1) / len(x), y.var(ddof=1) / len(y)
    if vx + vy <= 0:
        return 0.0, 1
    df = (vx + vy) ** 2 / (vx**2 / (len(x) - 1) + vy**2 / (len(y) - 1))
    return float(abs(x.mean() - y.mean()) / np.sqrt(vx + vy)), int(np.floor(df))


def _t_pooled(x: np.ndarray, y: np.ndarray) -> tuple[float, int]:
    """|t| and degrees of freedom of the difference of two means, the variance pooled."""
    df = len(x) + len(y) - 2
    sp = np.sqrt(((len(x) - 1) * x.var(ddof=1) + (len(y) - 1) * y.var(ddof=1)) / df)
    if sp <= 0:
        return 0.0, df
    return float(abs(x.mean() - y.mean()) / (sp * np.sqrt(1 / len(x) + 1 / len(y)))), df


def _flight_fit(samples: FlightSamples, effect: Effect, params: np.ndarray, scene: SceneSpec,
                ctx: FitContext) -> np.ndarray:
    """``params`` refitted by a robust regression of ``effect``'s accelerations on the flight
    samples' (the other parameters do not act in flight and stay)."""
    lo, hi = effect.bounds(ctx)
    lo_f, hi_f = np.where(np.isfinite(lo), lo, -1e6), np.where(np.isfinite(hi), hi, 1e6)
    x0 = np.clip(params, lo_f + 1e-9 * np.maximum(1, np.abs(lo_f)), hi_f - 1e-9 * np.maximum(1, np.abs(hi_f)))
    noise = 1.4826 * np.median(np.abs(samples.dacc - np.median(samples.dacc, axis=0)))

    def resid(p: np.ndarray) -> np.ndarray:
        return (seen_missing(effect, p, samples, scene)[0] - samples.dacc).reshape(-1)

    try:
        r = least_squares(resid, x0, bounds=(lo_f, hi_f), x_scale=effect.scale(ctx), loss="soft_l1",
                          f_scale=max(3 * noise, 1e-3), max_nfev=60)
    except ValueError:
        return params
    return r.x if np.all(np.isfinite(r.x)) else params


def flight_movers(samples: FlightSamples | None, effect: Effect, params: np.ndarray, scene: SceneSpec,
                  ctx: FitContext) -> list[int]:
    """Parts of ``effect`` whose parameters change the linear acceleration in flight.

    Why: only those can have taken up a force in flight. A rolling resistance (a force, but only
    in contact) or a spin damping (a torque) cannot; development case 5151007 (a rolling
    resistance and a box mass) lost its right ``rolling_resistance`` to a flight residual of
    0.05 m/s^2 that the box mass left, and ended ``consistent``.
    """
    if samples is None or not len(samples):
        return []
    base = _missing(effect, params, samples, scene)[0]
    scale = effect.scale(ctx)
    out, i = [], 0
    for k, e in enumerate(effect.parts if isinstance(effect, EffectSum) else (effect,)):
        sl = slice(i, i + e.n_params)
        i += e.n_params
        if not (e.has_forces and e.flight_regression):
            continue
        for j in range(sl.start, sl.stop):
            q = params.copy()
            q[j] += scale[j]
            if np.max(np.abs(_missing(effect, q, samples, scene)[0] - base)) > 1e-9:
                out.append(k)
                break
    return out
