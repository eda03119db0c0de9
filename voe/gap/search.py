"""Greedy search over candidate effects, each round's acceptance threshold calibrated by the
identical search on simulated clean data.

Why: adding any flexible term lowers the training error, so an effect is accepted only if it
lowers the *selection* error (episodes the fit never saw) by more than the same search reaches,
in the same round, on data simulated from the nominal scene (``NullSearch``: same candidates,
budget, refine step and selection windows; round 2 is calibrated on what a second effect gains
on clean data after a first one was forced in). Candidates whose selection error is within 10 %
of the winner's form a group. Within a group the winner is the member that predicts best on the
selection windows where the members' predictions differ (an impact-only effect and an
always-on drag differ in windows without an impact), not the one whose context words match; the
context decides only when no window tells them apart, and the group is then reported as
indistinguishable. Group members stay candidates in later rounds.

The gain is one minus the geometric mean over selection windows of each window's RMSE ratio
(after / before), not the ratio of pooled RMSEs. Why: a window with a collision whose outcome
flips with any small change carries most of the pooled squared error. Pooled, such a window let
a drag of 0.006 1/s "cut" clean data's error by 15 %; in the geometric mean every window counts
once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from voe.gap.context import frame_labels
from voe.gap.effects.base import Effect
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter
from voe.gap.mass_ratio import not_offered
from voe.gap.stand_in import is_stand_in, own_moved
from voe.parallel import parallel_map

GROUP_TOL = 0.10  # selection error ratio within 10 % of the winner's counts as indistinguishable
N_BOOT = 400
LOG_CLIP = 10.0  # a window's log SSE ratio is clipped to +-10 (a blown-up rollout counts, but finitely)


def window_gain(before_sse: np.ndarray, after_sse: np.ndarray | None, idx: np.ndarray | None = None) -> float | np.ndarray:
    """1 - geometric mean over windows of RMSE_after / RMSE_before.

    Args:
        before_sse, after_sse: (W,) per-window sums of squared residuals.
        idx: optional (N, W) bootstrap indices; then an (N,) array of resampled gains.
    """
    if after_sse is None or before_sse.size == 0 or not np.all(np.isfinite(after_sse)):
        return -np.inf if idx is None else np.full(len(idx), -np.inf)
    lr = np.clip(np.log(np.maximum(after_sse, 1e-300) / np.maximum(before_sse, 1e-300)), -LOG_CLIP, LOG_CLIP)  # (W,)
    if idx is None:
        return float(1.0 - np.exp(0.5 * lr.mean()))
    return 1.0 - np.exp(0.5 * lr[idx].mean(axis=1))


def gain_lower_bound(before_sse: np.ndarray, after_sse: np.ndarray | None, seed: int = 0, q: float = 0.05) -> float:
    """``q`` quantile of the gain under a paired bootstrap over selection windows.

    Why: one chaotic window (a collision whose outcome flips with any small change) can carry a
    spurious gain; requiring the gain to stay positive when windows are resampled rejects it.
    """
    if after_sse is None or before_sse.size == 0:
        return 0.0
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, before_sse.size, size=(N_BOOT, before_sse.size))  # (N_BOOT, W)
    return float(np.quantile(window_gain(before_sse, after_sse, idx), q))


def null_threshold(before_sse: np.ndarray, results: dict[str, FitResult], alpha: float = 0.05,
                   seed: int = 0) -> tuple[float, np.ndarray]:
    """(1 - alpha) quantile of the *best* candidate's gain on clean data, bootstrapped.

    Why: on clean data every gain is a false discovery, and the search keeps the best of many
    candidates, so the statistic to calibrate is the maximum over candidates. Each candidate's
    per-window error is resampled jointly, keeping the candidates' correlation.

    A candidate whose fit predicts the clean replicate's selection windows worse than the nominal
    model (point gain g < 0) counts at most as its mirror, -g: the search never accepts a loss,
    and all the replicate showed is that refitting it swings the chaotic windows by that much, so
    a data candidate could gain as much by flipping the same windows the other way; its resampled
    gains above -g measure only how far a few flipped windows swing under resampling.
    Development case 9028137 (a rolling resistance and a box 2.33 times heavier): since
    ``friction`` is fitted on the windows where a body slides (``Effect.sparse``), the null's
    friction went from the nominal 0.634 to 0.657 on those windows, chaotic at the truth, and
    flipped 3 of 12 selection windows (log SSE ratios -1.97, +2.55, +1.59): gain -9.2 %, but
    its resampled 95 % quantile, 15.6 % and 12.1 % in rounds 1 and 2, set both thresholds
    (every other candidate's quantile at most 2.5 %), and round 2's ``rolling_resistance``
    (11.1 %) was refused; counted at most as 9.2 % and 8.9 % both effects are named. Left out
    entirely (gapcomp22), floor patch 2758144's ``linear_drag`` (gain -19.0 %, quantile 20.3 %)
    no longer held round 1 above ``rolling_resistance``'s 5.7 %, and the patch was misnamed.

    Returns:
        The threshold and the (N_BOOT,) bootstrap distribution of the null's best gain.
    """
    sse = [r.window_sse for r in results.values() if r.window_sse is not None and np.all(np.isfinite(r.window_sse))]
    if before_sse.size == 0 or not sse:
        return 0.0, np.zeros(0)
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, before_sse.size, size=(N_BOOT, before_sse.size))  # (N_BOOT, W)
    point = np.array([window_gain(before_sse, a) for a in sse])  # (C,)
    cap = np.where(point < 0, -point, np.inf)  # (C,) a loser counts at most as its mirror: see above
    gains = np.minimum(np.stack([window_gain(before_sse, a, idx) for a in sse]), cap[:, None])  # (C, N_BOOT)
    best = gains.max(axis=0)
    return float(np.quantile(best, 1.0 - alpha)), best


@dataclass(frozen=True)
class Round:
    """One greedy round: selection RMSE before, every candidate's result, gain and bootstrap lower
    bound, the round's null threshold, and the winner (if accepted) with its group and how the
    group was decided."""

    before: float
    results: dict[str, FitResult]
    gains: dict[str, float]
    lower: dict[str, float]
    threshold: float | None  # None: the null's round was not needed (``voe.gap.greedy``)
    winner: str | None = None
    group: tuple[str, ...] = ()
    basis: str = ""
    tie: TieBreak | None = None
    stand_ins: dict[str, float] = field(default_factory=dict)  # members left out (``voe.gap.stand_in``): gains

    def to_dict(self) -> dict:
        return {"before": self.before, "threshold_gain": self.threshold, "winner": self.winner,
                "group": list(self.group), "basis": self.basis,
                "gains": {k: (round(g, 4) if np.isfinite(g) else None) for k, g in self.gains.items()},
                "stand_ins": {k: (round(g, 4) if np.isfinite(g) else None) for k, g in self.stand_ins.items()}}


@dataclass(frozen=True)
class RoundTask:
    """One search's round: fit every candidate in ``pool`` on top of ``current``; gains against
    ``before_sse`` (W,)."""

    fitter: FoldedFitter
    pool: dict[str, Effect]
    current: FitResult | None
    before_sse: np.ndarray
    note: Callable[[str], None] | None = None  # progress per fitted candidate (else ``fit_rounds``'s)


def fit_rounds(tasks: list[RoundTask], progress: Callable[[str], None] | None = None,
               n_jobs: int = 1) -> list[tuple[dict[str, FitResult], dict[str, float], dict[str, float]]]:
    """(results, gains, stand_ins) of every task, all candidate fits of all tasks in one parallel loop.

    A task with a current model leaves out of ``results`` and ``gains`` each member whose own
    part moves no selection window's prediction (``voe.gap.stand_in``); ``stand_ins`` holds
    their gains, for the record. A candidate that would put a mass on every body with nothing
    that sees absolute masses is not fitted at all (``voe.gap.mass_ratio``).

    Why together: the data's round and the null's same round are independent and equally
    expensive; fitting their candidates in one loop keeps ``n_jobs`` processes busy where two
    loops in a row would each end waiting for their slowest fit. Fits with more parameters (Powell,
    the slowest) are started first. With ``n_jobs > 1`` the fits run in forked processes, which
    inherit the fitters (pymunk scenes, recordings) instead of pickling them; each fit is
    deterministic, so results and their order do not depend on ``n_jobs``.
    """
    items = [(t, k) for t, task in enumerate(tasks) for k in task.pool if not _one_too_many(task, k)]
    items.sort(key=lambda it: -tasks[it[0]].pool[it[1]].n_params)  # stable: otherwise in pool order
    shooters = {id(t.fitter.shooter): t.fitter.shooter for t in tasks}
    start = {i: sh.n_rollouts for i, sh in shooters.items()}
    spent = dict.fromkeys(shooters, 0)
    found: dict[tuple[int, str], FitResult] = {}
    stand: set[tuple[int, str]] = set()
    for (t, key), (res, n_roll, moved) in zip(items, parallel_map(lambda it: _fit_one(it, tasks), items, n_jobs,
                                                                  start_method="fork"), strict=True):
        found[(t, key)] = res
        if is_stand_in(moved):
            stand.add((t, key))
        spent[id(tasks[t].fitter.shooter)] += n_roll
        note = tasks[t].note or progress
        if note:
            note(key)
    for i, sh in shooters.items():  # forked workers counted in their own copies
        sh.n_rollouts = start[i] + spent[i]
    out = []
    for t, task in enumerate(tasks):
        fitted = [k for k in task.pool if (t, k) in found]  # pool order: ties go to the first, as before
        gains = {k: window_gain(task.before_sse, found[(t, k)].window_sse) for k in fitted}
        results = {k: found[(t, k)] for k in fitted if (t, k) not in stand}
        out.append((results, {k: g for k, g in gains.items() if k in results},
                    {k: g for k, g in gains.items() if k not in results}))
    return out  # a gain is -inf for a rollout that blew up


def candidate_gains(fitter: FoldedFitter, candidates: dict[str, Effect], current: FitResult | None,
                    before_sse: np.ndarray, progress: Callable[[str], None] | None = None,
                    n_jobs: int = 1) -> tuple[dict[str, FitResult], dict[str, float]]:
    """Fit ``current + c`` for every candidate; gain = ``window_gain`` against ``before_sse`` (W,)."""
    return fit_rounds([RoundTask(fitter, candidates, current, before_sse)], progress, n_jobs)[0][:2]


def _one_too_many(task: RoundTask, key: str) -> bool:
    """Whether candidate ``key`` on top of the task's current model would put a mass on every body
    with nothing that sees absolute masses (``voe.gap.mass_ratio``): not offered."""
    return not_offered(task.fitter, (task.current.effect.parts if task.current is not None else ()) + task.pool[key].parts)


def _fit_one(item: tuple[int, str], tasks: list[RoundTask]) -> tuple[FitResult, int, float]:
    """Fit candidate ``key`` of task ``t``; returns the result, the rollouts it cost and, on top of
    a current model, how far its own part moves a selection window (``voe.gap.stand_in.own_moved``;
    ``inf`` in the first round)."""
    t, key = item
    task = tasks[t]
    n0 = task.fitter.shooter.n_rollouts
    res = task.fitter.fit_candidate(task.current, task.pool[key])
    moved = float("inf") if task.current is None else own_moved(task.fitter, res, task.pool[key])
    return res, task.fitter.shooter.n_rollouts - n0, moved


def context_match(effect_contexts: tuple[str, ...], located: set[str]) -> bool:
    """Whether an effect's contexts name a located context (``region x 0.1..0.5 m`` is ``region``)."""
    words = {c.split()[0] for c in located if c}
    return any(c in words for c in effect_contexts)


TIE_ALPHA = 0.05  # a group member is ruled out only if it loses on significantly more differing windows


def sign_p(d: np.ndarray) -> float:
    """One-sided sign-test p-value that ``d`` (per-window log SSE of a member minus the best's)
    is positive more often than by chance; exact ties count half.

    Why: a tie between effects is broken on the few windows where their predictions differ. On
    two or three such windows even a perfect record is no evidence (p >= 0.125), so the loser
    must stay in the reported group instead of being silently ruled out.
    """
    from scipy.stats import binomtest

    n = len(d)
    wins = float(np.sum(d > 0) + 0.5 * np.sum(d == 0))
    return float(binomtest(int(np.floor(wins)), n, 0.5, alternative="greater").pvalue) if n else 1.0


@dataclass(frozen=True)
class TieBreak:
    """How a tied group was decided on data: on ``n_differ`` selection windows where its members'
    predictions differ, ``unproven`` being the members a one-sided sign test could not rule out
    (the explanation says so in words; ``Round.basis`` keeps the same facts as text for gap.json)."""

    n_differ: int
    unproven: tuple[str, ...] = ()


def tie_break(fitter: FoldedFitter, group: list[str], results: dict[str, FitResult], candidates: dict[str, Effect],
              contexts: set[str], gains: dict[str, float],
              noise: float) -> tuple[str, tuple[str, ...], str, TieBreak | None]:
    """Winner of a group whose selection errors are within ``GROUP_TOL``.

    Members are compared on the selection windows where some pair's predictions differ by more
    than twice the noise floor ``noise`` (m, RMS over the window): the member with the lowest
    mean log error there wins, and members still within ``GROUP_TOL`` of it stay in the
    reported group. Without such windows the data cannot tell them apart, and the member whose
    contexts match the located contexts is named first.
    """
    res = {k: fitter.residuals(results[k].effect, results[k].fold_params) for k in group}
    n_w = len(res[group[0]])
    differ = np.zeros(n_w, dtype=bool)
    for i, a in enumerate(group):
        for b in group[i + 1:]:
            d = np.array([np.sqrt(np.mean((ra - rb) ** 2)) for ra, rb in zip(res[a], res[b], strict=True)])
            differ |= d > 2 * noise
    if differ.sum() >= 2:
        logs = {k: np.array([np.log(max(float(np.sum(r**2)), 1e-300)) for r, m in zip(res[k], differ, strict=True)
                             if m]) for k in group}  # (n_differ,) per member
        score = {k: float(v.mean()) for k, v in logs.items()}
        best = min(group, key=lambda k: score[k])
        close = {k for k in group if score[k] - score[best] <= 2 * np.log1p(GROUP_TOL)}
        unproven = {k for k in group if k not in close and sign_p(logs[k] - logs[best]) > TIE_ALPHA}
        kept = tuple(sorted(close | unproven, key=lambda k: score[k]))
        basis = f"chosen on the {int(differ.sum())} selection windows where the group's predictions differ"
        if unproven:
            basis += (f"; too few to rule out {', '.join(sorted(unproven))} (one-sided sign test p > {TIE_ALPHA:g})")
        return best, kept, basis, TieBreak(int(differ.sum()), tuple(sorted(unproven)))
    ranked = sorted(group, key=lambda k: (0 if context_match(candidates[k].contexts, contexts) else 1, -gains[k]))
    return ranked[0], tuple(ranked), "predictions differ in no selection window; named by the located context", None


COVER = 0.99  # a region holding this share of the contact samples is no region


def covers_contacts(fitter: FoldedFitter, res: FitResult) -> bool:
    """Whether the newest part of ``res``, a region effect, holds (nearly) every contact sample.

    Why: on data from a uniform floor, a region effect whose interval spans every place a body
    touched is the unlimited effect with two more parameters, and it can fit a little better
    (development case 5151011: a true global rolling resistance named
    ``rolling_resistance_region`` over x -2.31..5.57 m, every contact lying between -1.25 and
    5.47 m). The data then cannot tell a patch from the whole floor, and the simpler name is
    the honest one. Contact samples are frames labelled rolling, sliding or impact
    (``voe.gap.context.frame_labels``) of the fitting and selection episodes.
    """
    part = res.effect.parts[-1]
    if part.global_name is None:
        return False
    x0, x1 = sorted(res.params[-2:])
    sh = fitter.shooter
    eps = sorted({w.ep for f in fitter.folds for w in (f.pool or f.train) + f.test})
    mask = part.mask(sh.scene)
    xs = []
    for e in eps:
        ep = sh.episodes[e]
        lab = frame_labels(sh.scene, ep)  # (T, B)
        touch = np.isin(lab, ("rolling", "sliding", "impact")) & mask[None]
        xs.append(ep.pose[:, :, 0][touch])
    xs = np.concatenate(xs) if xs else np.zeros(0)
    return bool(xs.size) and float(np.mean((xs >= x0) & (xs <= x1))) >= COVER


def tie_keeps_global(winner: str, kept: tuple[str, ...], tie: TieBreak | None, candidates: dict[str, Effect]) -> bool:
    """Whether a region winner's unlimited form (``global_name``) stays in its group as
    indistinguishable: within ``GROUP_TOL`` on the windows where the members' predictions differ
    (not merely unproven there), or with no such windows at all.

    Why: a region effect is its global effect plus two edges (x0 -> -inf, x1 -> +inf gives it
    back), so the two are nested and the simpler one stands unless the data need the edges.
    Development case 8586037 (a true global ``rolling_resistance``, c = 0.087): the group held
    ``rolling_resistance_region`` (gain 25.2 %, c = 0.095 over x -0.57..4.61 m) and
    ``rolling_resistance`` (24.5 %), 3 selection windows told them apart, and the region was
    named although 9 % of the contact samples lay outside its interval, where the truth acted
    too. A member that is worse on those windows but not provably so (``TieBreak.unproven``)
    does not count: a real patch keeps its name when the global form predicts worse off the
    patch.
    """
    plain = candidates[winner].global_name
    if plain is None or plain not in kept:
        return False
    return tie is None or plain not in tie.unproven


def bound_limit(fitter: FoldedFitter, winner: str, kept: tuple[str, ...], results: dict[str, FitResult],
                candidates: dict[str, Effect]) -> str | None:
    """The key of the winner's nested limit (``Effect.limit_name``) if the winner's fit sits at
    the bound that stands for that limit in every fold (``Effect.at_limit``) and the limit stayed
    in the winner's group ``kept``; else None.

    Why: a spring whose anchor runs to infinity is a constant force, so ``spring_anchor`` nests
    ``constant_acceleration`` as a limit its bounded search cannot reach. A fit that stops at
    the anchor's bound was heading for that limit, and its anchor is an artefact of where the
    bound lies. If the limit then predicts the selection windows as well (it stayed in the
    group: within ``GROUP_TOL``, or on the windows where their predictions differ not ruled out
    by the sign test), the data do not need the extra parameter and the simpler effect is named,
    as ``tie_keeps_global`` names a region's global form. Unlike there, a member that is worse
    but not provably so counts: the winner's own fit ran to the edge of its family, towards the
    limit. Development cases 1531002 and 3629057 (a wind and a spin damping): round 1's group
    held ``spring_anchor`` (gains 37.4 % and 38.3 %, anchors at x = 12.4 m and y = -2.24 m, both
    bounds) and ``constant_acceleration`` (33.2 %, 34.0 %), and the spring was named.
    """
    part = candidates[winner]
    if part.limit_name is None:
        return None
    lim = next((k for k in kept if k != winner and candidates[k].name == part.limit_name), None)
    res = results.get(winner)
    if lim is None or res is None:
        return None
    n = part.n_params
    folds = fitter.folds
    if len(res.fold_params) != len(folds) or not all(part.at_limit(p[-n:], f.ctx) for f, p in zip(folds, res.fold_params,
                                                                                                 strict=True)):
        return None
    return lim


def choose(gains: dict[str, float], lower: dict[str, float], threshold: float) -> list[str]:
    """Candidates whose gain beats ``threshold``, whose bootstrap lower bound is positive and
    whose error is within ``GROUP_TOL`` of the best such candidate's (best first); [] if none."""
    eligible = {k: g for k, g in gains.items() if g > threshold and lower.get(k, 1.0) > 0}
    if not eligible:
        return []
    best = max(eligible, key=lambda k: eligible[k])
    floor = 1.0 - eligible[best]  # the winner's geometric-mean error ratio
    return sorted((k for k in eligible if 1.0 - eligible[k] <= floor * (1 + GROUP_TOL)), key=lambda k: -eligible[k])


def accept(fitter: FoldedFitter, res: FitResult, gain: float, before_sse: np.ndarray) -> FitResult:
    """The refine step (a longer fit from the winner's parameters), kept if it does not lose."""
    ref = fitter.refine(res)
    return ref if window_gain(before_sse, ref.window_sse) >= gain else res


def counted_map(fitter: FoldedFitter, fn: Callable, items: list, n_jobs: int = 1) -> list:
    """``[fn(x) for x in items]`` in ``n_jobs`` forked processes (they inherit ``fitter``; only
    items and results are pickled), with the simulator rollouts ``fn`` runs in a worker's copy of
    ``fitter.shooter`` added to this process's count, as if it had run here (the bench reports the
    count). One place for the candidate fits that the pair step, acceptance and re-selection run
    side by side; each ``fn`` is deterministic, so the results do not depend on ``n_jobs``."""
    def one(x):
        n0 = fitter.shooter.n_rollouts
        return fn(x), fitter.shooter.n_rollouts - n0

    runs = list(parallel_map(one, items, n_jobs, start_method="fork"))
    if n_jobs > 1 and len(items) > 1:  # parallel_map ran in workers: their rollouts are not counted here
        fitter.shooter.n_rollouts += sum(n for _, n in runs)
    return [r for r, _ in runs]


def accept_all(items: list[tuple[FoldedFitter, FitResult, float, np.ndarray]], n_jobs: int = 1) -> list[FitResult]:
    """``accept`` of each (fitter, result, gain, before_sse), in parallel: the data's winner and
    the null's forced candidate are refined at the same time (forked workers inherit the
    fitters; only indices and results are pickled)."""
    out = []
    runs = parallel_map(lambda i: _accept_one(items[i]), range(len(items)), n_jobs, start_method="fork")
    for (fitter, *_), (res, n_roll) in zip(items, runs, strict=True):
        out.append(res)
        if n_jobs > 1 and len(items) > 1:
            fitter.shooter.n_rollouts += n_roll  # counted in the forked worker's copy
    return out


def _accept_one(item: tuple[FoldedFitter, FitResult, float, np.ndarray]) -> tuple[FitResult, int]:
    n0 = item[0].shooter.n_rollouts
    return accept(*item), item[0].shooter.n_rollouts - n0
