"""Calibrate the gap finder's 95 % parameter intervals on development seeds, cheaply.

Why: the bench's interval coverage needs the whole finder per case (locate, null, search over
the whole library), far too slow to calibrate with. Here each case is a bench case (same scenes,
priors and noise), but only the *true* effect is fitted, exactly as the search fits a candidate
(fit on the fitting windows' subsample, then the refine step), and the interval is computed as
the finder does (``voe.gap.uncertainty``). It prints the coverage of the window bootstrap, the
episode bootstrap, and the smallest inflation factor of the episode bootstrap that covers the
target share, i.e. the figure ``voe.gap.uncertainty.INFLATE`` records, and the window bootstrap
both centred on the fit and shifted to the whole sample's one-step estimate
(``voe.gap.uncertainty.SHIFT``), each factor with its median interval width, and the interval
the finder reports since session 12 (the window bootstrap joined with the parametric bootstrap,
``voe.gap.parametric``): how often it holds the truth and leaves out the nominal value, for each
widening of the parametric half-width (``voe.gap.parametric.SPREAD``). Dev seeds only
(0..99), or ``--case-seeds``: cases of a development bench seed by id (seed * 1000 + index, truth
as the bench's cycle gives it), e.g. the identified cases whose intervals missed on 3629.

    python bench/gap_coverage.py --seeds 0-3 --truths friction,restitution --jobs 2
    python bench/gap_coverage.py --case-seeds 3629015,3629041
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from voe.gap.bench import TRUTHS, make_case
from voe.gap.parametric import SPREAD, basic_interval, replicate_errors
from voe.gap.search import window_gain
from voe.gap.stages import GapConfig, _folded, context_for, fit_windows, prepare
from voe.gap.uncertainty import TOL, one_step, quantiles, widen, window_terms
from voe.parallel import parallel_map


def one(args: tuple[int, str, bool]) -> dict:
    """Fit the true effect of one case and return what the intervals need."""
    seed, truth, a_shift = args
    case = make_case(np.random.default_rng(seed), truth)
    config = GapConfig()
    p = prepare(case.scene, case.episodes, (truth,), config)
    key = truth if truth in p.candidates else f"{truth}[{case.bodies[0]}]"
    data = _folded(p, p.shooter, p.episodes, p.bad, config, seed)
    before = data.heldout_sse(None, None)
    res = data.fit_candidate(None, p.candidates[key])
    ref = data.refine(res)
    if window_gain(before, ref.window_sse) >= window_gain(before, res.window_sse):
        res = ref
    ctx = context_for(p.scene, [p.episodes[i] for i in p.split.fit])
    terms = window_terms(p.shooter, p.sigma, fit_windows(p, p.split.fit, config), res.effect, res.params, ctx,
                         config.fit.f_scale)
    lo_b, hi_b = res.effect.bounds(ctx)
    # window bootstrap (BY_EPISODE False), episode bootstrap, and the window bootstrap both centred on the fit
    # (shift off) and on the whole sample's one-step estimate (shift on), from the same fit
    q = {(by, sh): quantiles(terms, res.effect, res.params, ctx, seed, by, shift=sh)
         for by, sh in ((False, False), (True, a_shift), (False, True))}
    errs = replicate_errors(p, p.split.fit, config.fit_window, res.effect, res.params, ctx, config.fit.f_scale, seed)
    return {"seed": seed, "truth": truth, "params": res.params, "est": one_step(terms, res.effect, res.params, ctx),
            "errs": errs, "true": case.params, "q": q, "q_shift": a_shift,
            "scale": res.effect.scale(ctx), "lo_b": lo_b, "hi_b": hi_b, "nominal": res.effect.nominal(ctx)}


def interval(r: dict, by_episode: bool, k: float, tol: float, shift: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(P,) ends of the interval (window or episode bootstrap, widened by ``k``, floor ``tol``
    scales), as ``voe.gap.uncertainty.bootstrap`` makes it."""
    q_lo, q_hi, blind = r["q"][(by_episode, shift or by_episode and r["q_shift"])]
    lo, hi = widen(r["params"], q_lo, q_hi, tol / TOL * r["scale"], k)
    lo, hi = np.clip(lo, r["lo_b"], r["hi_b"]), np.clip(hi, r["lo_b"], r["hi_b"])
    return np.where(blind, r["lo_b"], lo), np.where(blind, r["hi_b"], hi)


def parametric_interval(r: dict, spread: float = SPREAD) -> tuple[np.ndarray, np.ndarray]:
    """(P,) ends of the finder's interval with the parametric bootstrap
    (``voe.gap.uncertainty.bootstrap`` given ``errors``): the hull of the fit, the shifted window
    bootstrap and the bias-corrected parametric interval, its half-width widened ``spread`` times
    (the finder's: ``voe.gap.parametric.SPREAD``)."""
    q_lo, q_hi, blind = r["q"][(False, True)]
    p_lo, p_hi = basic_interval(r["est"], r["errs"], spread=spread)
    lo, hi = widen(r["params"], np.fmin(q_lo, p_lo), np.fmax(q_hi, p_hi), r["scale"], 1.0)
    lo, hi = np.clip(lo, r["lo_b"], r["hi_b"]), np.clip(hi, r["lo_b"], r["hi_b"])
    return np.where(blind, r["lo_b"], lo), np.where(blind, r["hi_b"], hi)


def holds(lo: np.ndarray, hi: np.ndarray, r: dict) -> tuple[bool, bool]:
    """Whether ``[lo, hi]`` holds every true parameter, and whether it leaves out some nominal
    value (the effect is established, ``voe.gap.uncertainty.established``)."""
    t, nom = r["true"], r["nominal"]
    return (bool(np.all(np.isnan(t) | ((lo <= t) & (t <= hi)))),
            bool(np.any(np.isfinite(nom) & ((nom < lo) | (nom > hi)))))


def covered(r: dict, by_episode: bool, k: float, tol: float, shift: bool = False) -> bool:
    """Whether the interval contains every true parameter."""
    lo, hi = interval(r, by_episode, k, tol, shift)
    t = r["true"]
    return bool(np.all(np.isnan(t) | ((lo <= t) & (t <= hi))))


def established_at(r: dict, k: float) -> bool:
    """Whether the shifted window-bootstrap interval widened by ``k`` leaves out some nominal
    value (the finder's test of whether the effect is established, ``uncertainty.established``)."""
    lo, hi = interval(r, False, k, TOL, True)
    nom = r["nominal"]
    return bool(np.any(np.isfinite(nom) & ((nom < lo) | (nom > hi))))


def width(rows: list[dict], k: float, shift: bool) -> float:
    """Median over cases of the window-bootstrap interval's mean width, relative to the true value
    (parameter scale where the truth is near zero)."""
    out = []
    for r in rows:
        lo, hi = interval(r, False, k, TOL, shift)
        ref = np.maximum(np.abs(np.nan_to_num(r["true"], nan=0.0)), r["scale"])
        out.append(float(np.mean((hi - lo) / ref)))
    return float(np.median(out))


DEV_BENCH_SEEDS = (*range(100), 5151, 6263, 7741, 3629, 1531, 8586, 7857)  # PLAN.md: the gap development seeds
FACTORS = (1.0, 1.5, 2.0, 2.5, 3.0, 4.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="0-3", help="dev seeds a-b (0..99 only)")
    ap.add_argument("--truths", default=",".join(t for t in TRUTHS if t != "none"))
    ap.add_argument("--target", type=float, default=0.95, help="share of cases the calibrated interval covers")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--episodes", action="store_true", help="list per case for the episode bootstrap")
    ap.add_argument("--shift", action="store_true", help="centre the bootstrap on the whole sample's one-step estimate")
    ap.add_argument("--case-seeds", default="",
                    help="comma-separated case ids of a dev bench seed's cycle (e.g. 3629015), truth as the bench cycles")
    a = ap.parse_args()
    lo_s, hi_s = (int(x) for x in a.seeds.split("-"))
    if not (0 <= lo_s <= hi_s <= 99):
        ap.error("development seeds are 0..99")
    todo = [(s, t) for s in range(lo_s, hi_s + 1) for t in a.truths.split(",")]
    if a.case_seeds:
        ids = [int(x) for x in a.case_seeds.split(",")]
        if any(i // 1000 not in DEV_BENCH_SEEDS for i in ids):
            ap.error(f"case ids must come from a development bench seed {DEV_BENCH_SEEDS}")
        todo = [(i, TRUTHS[(i % 1000) % len(TRUTHS)]) for i in ids]
    todo = [(s, t, a.shift) for s, t in todo]
    t0 = time.time()
    rows = list(parallel_map(one, todo, a.jobs))
    n = len(rows)
    which = f"cases {a.case_seeds}" if a.case_seeds else f"{a.truths}; seeds {a.seeds}"
    print(f"gap coverage: {n} cases ({which}), {time.time() - t0:.0f} s")
    for r in rows:
        ks = [k for k in FACTORS if covered(r, a.episodes, k, TOL)]
        ks1 = [k for k in FACTORS if covered(r, False, k, TOL, True)]
        est = [k for k in FACTORS if established_at(r, k)]
        cov, est_p = holds(*parametric_interval(r), r)
        print(f"  {r['truth']:22s} seed {r['seed']:2d} fit {np.round(r['params'], 4)} true {np.round(r['true'], 4)} "
              f"covered from k = {min(ks, default='-')} (shifted to the one-step estimate: {min(ks1, default='-')}); "
              f"shifted interval excludes the nominal up to k = {max(est, default='-')}; parametric: holds the truth "
              f"{cov}, established {est_p} (replicate bias {np.round(np.nanmean(r['errs'], axis=0), 4)})")
    par = [holds(*parametric_interval(r), r) for r in rows]
    old = [holds(*interval(r, False, 2.5, TOL, True), r) for r in rows]
    for name, v in (("parametric + window bootstrap (the finder's)", par), ("window bootstrap shifted, 2.5x", old)):
        print(f"{name}: holds the truth {sum(c for c, _ in v)}/{n}, leaves out the nominal value (established) "
              f"{sum(e for _, e in v)}/{n}, both {sum(c and e for c, e in v)}/{n}")
    for k in FACTORS:
        v = [holds(*parametric_interval(r, k), r) for r in rows]
        mark = " (the finder's)" if k == SPREAD else ""
        print(f"parametric + window bootstrap, spread {k}{mark}: "
              f"holds the truth {sum(c for c, _ in v)}/{n}, established {sum(e for _, e in v)}/{n}")
    for sh in (False, True):
        for k in FACTORS:
            c = sum(covered(r, False, k, TOL, sh) for r in rows)
            print(f"window bootstrap{', shifted' if sh else ''}, k = {k}: {c}/{n} = {100 * c / n:.0f} %, "
                  f"median relative width {width(rows, k, sh):.3f}")
    for by in (False, True):
        for k in FACTORS:
            c = sum(covered(r, by, k, TOL) for r in rows)
            print(f"{'episode' if by else 'window'} bootstrap, k = {k}: {c}/{n} = {100 * c / n:.0f} %")
            if c >= a.target * n:
                break
    for tol in (0.03, 0.1):
        for k in FACTORS:
            c = sum(covered(r, a.episodes, k, tol) for r in rows)
            print(f"{'episode' if a.episodes else 'window'} bootstrap, floor {tol} scales, k = {k}: {c}/{n} = "
                  f"{100 * c / n:.0f} %")
            if c >= a.target * n:
                break

if __name__ == "__main__":
    main()
