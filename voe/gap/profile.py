"""Where an interval is blind, the values the fitting windows cannot tell from the fit (a profile scan).

Why: ``voe.gap.uncertainty`` steps from the fit by Gauss-Newton, so a parameter that moves no
window's prediction *at the fit* gets its whole bounded range. A saturated effect is like that:
above a friction of about 1 the box sticks and any higher value predicts the same, so the cost
is flat at the fit, yet the nominal 0.6 predicts very differently. Development case 7857016
(friction 1.44, fitted 1.442, selection gain 72 % against a null threshold of 7.6 %) got the
interval [0, 3], which holds the nominal value, and the right effect was dropped as not
established. Flat locally is not flat everywhere: scanning the parameter over its range (the
others held at the fit) finds where the prediction starts to change, and there a paired
bootstrap over fitting windows says whether the fit predicts consistently better.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect, FitContext
from voe.gap.nuisance import projected_sse
from voe.gap.search import gain_lower_bound, window_gain
from voe.gap.shooting import Shooter, Window, window_sse

N_GRID = 24  # scan points across the bounded range (plus the fit and the nominal value)
Q = 0.05  # a value is ruled out if the fit's gain over it has a positive bootstrap 5 % quantile
REL = 1e-6  # a window whose error changes by less than this share does not inform (rollouts are deterministic)
MIN_INFORM = 2  # windows; a bootstrap over one window is that window


def scan_grid(lo: float, hi: float, extra: tuple[float, ...] = ()) -> np.ndarray:
    """Sorted scan values: geometric when the range is positive and spans more than a decade
    (a mass scale, 0.05-20), linear otherwise, plus the ``extra`` values inside the range."""
    grid = np.geomspace(lo, hi, N_GRID) if lo > 0 and hi / lo > 10 else np.linspace(lo, hi, N_GRID)
    more = [float(x) for x in extra if np.isfinite(x) and lo <= x <= hi]
    return np.unique(np.concatenate([grid, more]))


def ruled_out(fit_sse: np.ndarray, sse: np.ndarray, q: float = Q) -> bool:
    """Whether the fit predicts the windows better than a scanned value: on the windows whose
    error the value changes (at least ``MIN_INFORM``), the gain of the fit over it
    (``voe.gap.search.window_gain``, every window once) is positive and so is its bootstrap
    ``q`` quantile. Equal predictions (the flat, saturated side) are never ruled out.

    Why only the windows it changes: a friction acts in the few windows where the box slides,
    and which windows those are is fixed by the recordings, not drawn by the noise (as
    ``voe.gap.uncertainty`` stratifies by information). Over all windows a resample holds none of
    k informative ones with probability about exp(-k), and the bootstrap quantile is then zero:
    7857016's nominal friction was not ruled out although 72 % of the selection error went with it.
    """
    moved = np.abs(sse - fit_sse) > REL * np.maximum(fit_sse, 1e-300)  # (W,)
    if moved.sum() < MIN_INFORM:
        return False
    a, b = sse[moved], fit_sse[moved]
    return bool(window_gain(a, b) > 0 and gain_lower_bound(a, b, q=q) > 0)


def profile_interval(shooter: Shooter, windows: list[Window], effect: Effect, params: np.ndarray, j: int,
                     ctx: FitContext) -> tuple[float, float]:
    """The hull of the fit and of the scanned values of parameter ``j`` (the rest at ``params``)
    that the fitting ``windows`` do not rule out (``ruled_out``); the whole bounded range if the
    range is not finite."""
    lo_b, hi_b = effect.bounds(ctx)
    lo, hi = float(lo_b[j]), float(hi_b[j])
    if not (np.isfinite(lo) and np.isfinite(hi)) or not windows:
        return lo, hi
    fit_sse = window_sse(shooter, windows, effect, params)  # (W,)
    kept = [float(params[j])]
    for v in scan_grid(lo, hi, (float(params[j]), float(effect.nominal(ctx)[j]))):
        p = np.asarray(params, dtype=float).copy()
        p[j] = v
        sse = window_sse(shooter, windows, effect, p)
        if not np.all(np.isfinite(sse)) or ruled_out(fit_sse, sse):
            continue
        kept.append(float(v))
    return min(kept), max(kept)


def nominal_side(shooter: Shooter, sets: list[list[Window]], effect: Effect, params: np.ndarray, j: int,
                 ctx: FitContext, lo: float, hi: float,
                 bases: list[list[np.ndarray | None]] | None = None) -> tuple[float, float]:
    """The interval [``lo``, ``hi``] of parameter ``j`` (the rest at ``params``), which holds its
    nominal value, asked directly whether the windows rule that value out: by ``ruled_out`` on
    each of the window ``sets`` separately (the fitting episodes' windows and the selection
    episodes'). If they do, that side ends at the scanned value between the nominal value and the
    fit farthest from the fit that they do not rule out (the fit itself if none); else the
    interval is returned unchanged.

    Why: the local interval (``voe.gap.uncertainty``, ``voe.gap.parametric``) linearises the cost
    at the fit, and friction and rolling resistance are hinges: once the body sticks or stops,
    more of the effect predicts the same, so the windows that rule out a low value can carry no
    curvature at the fit. Development case 2758081 (``friction`` 1.27 against the scene's 0.46,
    fitted 1.04, selection gain 33 %): two of 16 fitting windows had curvature at the fit, the
    one Gauss-Newton step went from 1.04 to 0.69 although the cost there is higher (26095
    against 25168), and resamples of the weakest informative window stepped to the bound: interval
    [0, 1.27], dropped as not established, while the fitting windows' soft-L1 cost at the nominal
    0.46 is 39557, three windows 1.7e3, 5.1e3 and 9.2e3 worse and one 2.1e3 better. Development
    case 4593094 (friction 1.20, fitted 1.41): one of 8 parametric replicates stepped 0.61 low and
    set the whole interval's width ([0.31, 2.61], the window bootstrap's [1.17, 1.41]). The
    profile scan already replaces a blind interval (``profile_interval``); this asks the same
    question, by the same test, of the one value the decision is about.

    Why each set separately: the fit was tuned on the fitting windows, so there it beats any
    other value, noise included, and a dense effect's small in-sample gain is consistent
    across windows. Development case 2758101 (``restitution``, with a provisional
    ``constant_acceleration`` on top): g_y = -0.010 (local interval [-0.165, 0.147]) was ruled
    out on the fitting windows (gain 4.5 %, 5 % quantile 1.2 %) but not on the selection windows
    (quantile -0.5 %); with both together it was kept, a false name. The selection windows alone
    are held out from the fit but chose the effect; a value both rule out is ruled out by the
    data that fitted it and by data that did not. With no selection windows (cross-validation)
    nothing is ruled out here and the local interval stands. Since ``voe.gap.check`` asks only
    hinge parts (``Effect.saturates``), and since session 20 only on the fitting episodes'
    windows, ``sets`` holds one set there (see ``voe.gap.check.model_intervals``).

    With ``bases`` (per set, per window, ``voe.gap.nuisance.velocity_bases``) each window's error
    is taken with its start-velocity directions projected out (``voe.gap.nuisance.projected_sse``).
    Why: a hinge takes one sign of the noise. A window starts from a velocity estimated from noisy
    samples (about 10 mm/s off at 1 mm noise), and a ball rolling on 5-10 mm/s too fast is
    predicted better by any rolling resistance; 5-10 mm/s too slow, no rolling resistance can help
    it, and the fit stays at zero. So a clean case whose fitting windows happen to overestimate
    more often than not fits a small positive value, which beats zero on those very windows.
    Five clean cases of the untouched runs of sessions 52-58 were named ``rolling_resistance``
    that way (4497215, 4497285, 1829321, 3511310, 9260277: c_rr 0.0022-0.0031, each the lower
    end of its interval because the fitting windows ruled out everything below it). The start
    estimate is not biased (session 60, ``docs/bench-runs/dev-s60/vbias.py``: over 138 rolling
    windows of 40 clean cases, +0.7 +- 0.9 mm/s along the motion): it is noise, which a fit that
    also freed the start velocity would not mistake for an effect. With the start velocities
    projected out (``docs/bench-runs/dev-s60/vproj.py``, a grid fit on the fitting windows), all
    five fit c_rr 0 to 0.001 and gain nothing on the selection windows, while ten true rolling
    resistances of the same runs (c_rr 0.042-0.096) keep selection gains of 39-67 % and fits
    within a grid step of the truth.
    """
    nom = float(effect.nominal(ctx)[j])
    x = float(params[j])
    if not sets or not all(sets) or not np.isfinite(nom) or nom == x:
        return lo, hi

    def errors(k: int, p: np.ndarray) -> np.ndarray:  # (W_k,) window errors of set k
        if bases is None:
            return window_sse(shooter, sets[k], effect, p)
        return projected_sse(shooter, sets[k], bases[k], effect, p)

    fit_sse = [errors(k, params) for k in range(len(sets))]  # (W_k,) each

    def out(v: float) -> bool:
        p = np.asarray(params, dtype=float).copy()
        p[j] = v
        for k, f in enumerate(fit_sse):
            sse = errors(k, p)
            if not (np.all(np.isfinite(sse)) and ruled_out(f, sse)):
                return False
        return True

    if not out(nom):
        return lo, hi
    lo_b, hi_b = effect.bounds(ctx)
    between = [float(v) for v in scan_grid(float(lo_b[j]), float(hi_b[j])) if min(nom, x) < v < max(nom, x)]
    kept = [x] + [v for v in between if not out(v)]
    return (min(kept), hi) if nom < x else (lo, max(kept))
