"""The finder's first stages, each returning a frozen result: prepare the problem, locate the
mismatch, and search for effects against the identical search on clean data.

Why stages: one long method that fills twenty attributes, read back from ``self`` by every
helper, hides which step uses what. Here each step takes the results it needs and returns its
own (``Problem`` -> ``Location`` -> ``Search``), and ``voe.gap.check`` turns them into the
verdict.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from voe.errors import DataError
from voe.gap.context import frame_labels, near_contact
from voe.gap.departure import ALPHA, departure_p, local_replicates
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import Effect, FitContext
from voe.gap.fit import FitConfig, FitResult, Fitter
from voe.gap.folds import FoldedFitter
from voe.gap.greedy import SearchResult, greedy
from voe.gap.jitter import Jitter, timing_jitter
from voe.gap.locate import CLEAN, by_bar, locate, locate_local, window_z
from voe.gap.null import NullRound, NullSearch
from voe.gap.prefit import FINE_HALF, flight_samples
from voe.gap.recordings import Episode, load_recordings
from voe.gap.scene import load_scene, resolve_joints
from voe.gap.shooting import Shooter, Window, choose_half, make_windows, noise_model
from voe.gap.split import Split, split_episodes
from voe.gap.synth import null_like
from voe.sim.scenefile import SceneSpec


@dataclass(frozen=True)
class GapConfig:
    """Knobs of the search. Budgets are simulated seconds per evaluation (windows subsampled)."""

    fit_window: float = 1.0
    locate_window: float = 1.0
    substep: float | None = None  # default 1 ms, 0.5 ms for scenes with joints
    fit_budget: float = 8.0  # the data and the null alike
    test_budget: float = 20.0  # selection windows: simulated once per candidate, cheap, and many steady the gain
    cross_fit: bool = False  # halves swap fitting and selection (voe.gap.split); twice the fitting work
    cross_fit_budget: float = 50.0  # selection seconds over both folds when cross-fitted: every window of 10 episodes of 3 s
    second_look: bool = True  # a three-way split that names nothing is looked at again, cross-fitted (voe.gap.finder)
    second_look_test_gain: float = 0.05  # the second look's name must lower the test RMSE by this fraction (carry_over.short_on_test)
    min_gain: float = 0.05  # practical floor: a selection gain below 5 % is never accepted
    null_alpha: float = 0.05  # the threshold is the null's best gain at this upper quantile
    gain_lower_q: float | None = 0.05  # the gain's bootstrap quantile over selection windows must be > 0
    z_min: float = 5.0
    deepen_factor: float = 2.0  # a test window's rise must pass this many times max(replicate z, threshold)
    deepen_replicates: int = 10  # the model's own window-local replicates of such a window (0: none; voe.gap.carry_over.deepened)
    deepen_growth: float = 1.2  # ... and the window's z must grow by this factor (1: any growth; voe.gap.carry_over.deepened)
    deepen_refit: bool = True  # ... and must still depart with each start velocity refitted (voe.gap.start_refit)
    fit: FitConfig = FitConfig()


@dataclass(frozen=True)
class Problem:
    """Scene, recordings and everything estimated from them before any search."""

    scene: SceneSpec
    episodes: list[Episode]
    sigma: np.ndarray  # (B, 3) noise floor
    phi: np.ndarray  # (B, 3) AR(1) coefficient of the noise (0: white)
    substep: float
    half: int  # velocity-fit half-width
    bad: dict[int, np.ndarray]  # per episode, (T,) samples a window must not start at
    split: Split
    candidates: dict[str, Effect]
    shooter: Shooter
    jitter: Jitter | None = None  # timing jitter the clean replicates reproduce (voe.gap.jitter), if clear


@dataclass(frozen=True)
class Location:
    """Where the recordings leave the nominal model, with the clean replicate that calibrated it."""

    windows: list[Window]
    located: list[dict]  # ``Located.to_dict()``; ``bar`` says which bar located each (``locate_parts``)
    z_threshold: float
    z_strong: float  # the clean replicate's largest window z: beyond it a stretch is a mismatch
    null_episodes: list[Episode]
    departure_p: float = 1.0  # paired test: data's window z above the replicate's (voe.gap.departure)


@dataclass(frozen=True)
class Search:
    """The data's greedy search and the null's rounds; ``fitter`` scores selection windows."""

    result: SearchResult
    null: tuple[NullRound, ...]
    fitter: FoldedFitter
    null_rollouts: int = 0  # windows the null's search simulated (the data's: ``Problem.shooter.n_rollouts``)


def prepare(scene: str | Path | SceneSpec, recordings: str | Path | pd.DataFrame | list[Episode],
            effects: tuple[str, ...], config: GapConfig) -> Problem:
    """Load and check inputs, estimate noise and the velocity-fit width, split the episodes."""
    names = [EFFECTS.resolve(n) for n in effects]  # fail fast on typos
    spec, eps = _load(scene, recordings)
    try:
        split = split_episodes(len(eps), config.cross_fit)
    except ValueError as exc:
        raise DataError(f"recordings {recordings if not isinstance(recordings, list) else '<list>'}: {exc}") from exc
    sub = config.substep or (5e-4 if spec.joints else 1e-3)
    loc = make_windows(eps, list(range(len(eps))), config.locate_window)
    half = choose_half(spec, eps, loc, sub)
    sigma, phi = noise_model(eps)
    return Problem(spec, eps, sigma, phi, sub, half, _bad_starts(spec, eps, half), split,
                   _candidates(names, spec), Shooter(spec, eps, sub, half), timing_jitter(eps, phi))


def locate_step(p: Problem, config: GapConfig, rng: np.random.Generator) -> Location:
    """Window z-scores of the data against a clean replicate's; located stretches."""
    _, finish = locate_parts(p, config, rng)
    return finish()


@dataclass(frozen=True)
class PendingLocation:
    """The clean replicate, known before the rest of the location, and the call that gives the
    rest (``locate_parts``' second part, or its result from another process)."""

    null_episodes: list[Episode]
    rest: Callable[[], Location]


def locate_parts(p: Problem, config: GapConfig,
                 rng: np.random.Generator) -> tuple[list[Episode], Callable[[], Location]]:
    """``locate_step`` in two parts: the clean replicate (drawn from ``rng``), and the call that
    computes the rest: window z-scores of the data and the replicate, the located stretches and
    the departure test (window-local clean replicates, drawn from ``rng``, which must not be used
    between the two).

    Why two: the search needs only the clean replicate to start (its null fits on it), and the
    located contexts only to break a tie after its first round; the departure test only the
    verdict reads. The finder runs the second part on another process while the search's first
    round fits (``voe.gap.parallel.Ahead``); the window z-scores (about 0.3 s of
    ``bench/gap_speed.py``) used to keep the main process busy while the fitting workers waited.
    The same call on the same inputs gives the same location either way.

    Why a second bar (session 53): a stretch is located when its median window z passes the clean
    replicate's 95th-percentile window z, one bar for every window. In the bench's arena a few
    chaotic windows (a ball striking a box) set that bar high, so a gust that raises many windows
    well above their own clean replicates can pass none: the untouched runs of seeds 7241 and
    6219 left one gust each ``consistent`` (7241143: departure p = 0.0004, nothing above the bar
    z = 21.2), the verdict saying nothing while the departure test said the data depart. So
    when nothing passes that bar and the departure p is below ``ALPHA``, the windows whose z
    exceeds every one of their own window-local clean replicates (the departure test's, and
    ``z_min``) are located instead (``voe.gap.locate.locate_local``, each stretch marked
    ``bar = "local"``). Counted on 1152 cases of six development seeds (7241, 5025, 8657,
    1066, 6219, 8367; the locate stage alone, the finder's own draws;
    docs/bench-runs/dev-s52/rel_count.txt): clean cases called ``unexplained`` white 3/540 and
    coloured 0/540 with it or without (the same three), gusts unexplained 34 -> 36 of 36, floor
    patches unchanged (26 of 36). Such stretches do not steer the search's ties (``search_step``
    reads only the stretches the first bar located), so a case that names an effect is searched
    as before.
    """
    windows = make_windows(p.episodes, list(range(len(p.episodes))), config.locate_window, bad_start=p.bad)
    null_eps = null_like(p.scene, p.episodes, p.sigma, rng, p.substep, p.phi, p.jitter)

    def finish() -> Location:
        null_shooter = Shooter(p.scene, null_eps, p.substep, p.half)
        z_null = window_z(null_shooter, windows, p.sigma).max(axis=(1, 2))  # (W,)
        z_thr = float(max(config.z_min, np.quantile(z_null, 0.95)))
        z_strong = float(max(config.z_min, np.max(z_null)))
        z = window_z(p.shooter, windows, p.sigma)
        located = [x.to_dict() for x in locate(p.shooter, windows, z, z_thr)]
        local = local_replicates(p.shooter, windows, p.sigma, p.phi, rng, jitter=p.jitter)  # (R, W) (voe.gap.departure)
        dp = departure_p(z.max(axis=(1, 2)), z_null, local)
        if not located and dp < ALPHA:  # departs as a whole, nothing above the one bar: each window against its own
            bars = np.maximum(local.max(axis=0), config.z_min)  # (W,)
            located = [x.to_dict() for x in locate_local(p.shooter, windows, z, bars)]
        return Location(windows, located, z_thr, z_strong, null_eps, dp)

    return null_eps, finish


def search_step(p: Problem, loc: Location | PendingLocation, config: GapConfig, max_effects: int, seed: int,
                n_jobs: int = 1, progress: Callable[[str], None] | None = None,
                on_model: Callable[[FitResult], None] | None = None) -> Search:
    """The greedy search on the data, each round judged against the same round on clean data;
    ``on_model`` is called with each model it accepts (``voe.gap.greedy.greedy``). With a
    ``PendingLocation`` the located contexts are asked for only when a tie needs them."""
    note = progress or (lambda s: None)
    data = _folded(p, p.shooter, p.episodes, p.bad, config, seed)
    null_shooter = Shooter(p.scene, loc.null_episodes, p.substep, p.half)
    null_bad = _bad_starts(p.scene, loc.null_episodes, p.half)  # the replicate's own contacts, not the data's
    null = NullSearch(_folded(p, null_shooter, loc.null_episodes, null_bad, config, seed), p.candidates, config.null_alpha,
                      config.min_gain, seed, lambda k: note(f"null: {k}"), n_jobs)
    def contexts() -> set[str]:
        located = loc.located if isinstance(loc, Location) else loc.rest().located
        return {x["context"] for x in by_bar(located, CLEAN)} or _all_labels(p.scene, p.episodes)

    noise = float(np.median(p.sigma[:, :2]))
    res = greedy(data, p.candidates, null, max_effects, contexts, noise, lambda k: note(f"fit: {k}"),
                 config.gain_lower_q, n_jobs, on_model)
    return Search(res, null.result(), data, null_shooter.n_rollouts)


def context_for(scene: SceneSpec, episodes: list[Episode]) -> FitContext:
    """Bounds, scales and regression starts from ``episodes`` (the fitting episodes only)."""
    pos = np.concatenate([e.pose[:, :, :2].reshape(-1, 2) for e in episodes])
    vel = np.concatenate([np.diff(e.pose, axis=0).reshape(-1, 3) / np.median(np.diff(e.t)) for e in episodes])
    return FitContext(scene, pos.min(axis=0), pos.max(axis=0),
                      float(np.median(np.linalg.norm(vel[:, :2], axis=1))), float(np.median(np.abs(vel[:, 2]))),
                      flight_samples(scene, episodes), flight_samples(scene, episodes, half=FINE_HALF))


def fit_context(p: Problem, ids: tuple[int, ...] | None = None) -> FitContext:
    """``context_for`` the episodes ``ids`` (default: the fitting episodes): the one context the
    check, the drift test and the checks started ahead (``voe.gap.speculate``) all bound in."""
    return context_for(p.scene, [p.episodes[i] for i in (p.split.fit if ids is None else ids)])


def fit_windows(p: Problem, ids: tuple[int, ...], config: GapConfig) -> list[Window]:
    """Back-to-back windows of episodes ``ids`` (bad starts moved on)."""
    return make_windows(p.episodes, list(ids), config.fit_window, bad_start=p.bad)


def _folded(p: Problem, shooter: Shooter, episodes: list[Episode], bad: dict[int, np.ndarray], config: GapConfig,
            seed: int) -> FoldedFitter:
    """One ``Fitter`` per fold on ``episodes`` (the data or its clean replicate), windows cut by
    ``bad`` (per episode, (T,) starts refused), which must be the contacts of ``episodes`` themselves.

    Why its own contacts: the replicate follows the nominal physics from each episode's first
    state, so its impacts fall elsewhere than the data's; cut by the data's, its windows started
    inside its own impacts, where any damping candidate "gains" on the garbage start velocity and
    the threshold rose (development case 1531056: 7 of 15 null selection windows). The same seed
    draws the subsample for the data and the null.
    """
    rng = np.random.default_rng(seed)
    w = config.fit_window
    folds = p.split.fit_select
    budget = config.cross_fit_budget if p.split.cross_fitted else config.test_budget
    out = []
    for fit_ids, sel_ids in folds:
        train = _subsample(make_windows(episodes, list(fit_ids), w, bad_start=bad), config.fit_budget, w, rng)
        sel = _subsample(make_windows(episodes, list(sel_ids), w, stride=w / 2, bad_start=bad),
                         budget / len(folds), w, rng)
        pool = make_windows(episodes, list(fit_ids), w, stride=w / 2, bad_start=bad)
        ctx = context_for(p.scene, [episodes[i] for i in fit_ids])
        out.append(Fitter(shooter, p.sigma, train, sel, ctx, config.fit, pool=pool))
    return FoldedFitter(out)


def _load(scene: str | Path | SceneSpec, recordings: str | Path | pd.DataFrame | list[Episode]) -> tuple[SceneSpec, list[Episode]]:
    if isinstance(scene, SceneSpec):
        spec, joints = scene, None
    else:
        spec, joints, _ = load_scene(scene)
    if isinstance(recordings, list):
        eps = recordings
        for e in eps:  # in-memory episodes skip the file checks; a wild value must still stop here
            bad = ~np.isfinite(e.pose) | (np.abs(e.pose) > 1e6)
            if bad.any() or not np.all(np.isfinite(e.t)):
                k = int(np.argwhere(bad)[0][0]) if bad.any() else 0
                raise DataError(f"episode {e.id}: non-finite or impossibly large pose at sample {k}")
    elif isinstance(recordings, pd.DataFrame):
        eps = load_recordings("<dataframe>", spec, recordings)
    else:
        eps = load_recordings(recordings, spec)
    if joints:
        spec = resolve_joints(spec, joints, eps[0].pose[0])
    return spec, eps


def _bad_starts(scene: SceneSpec, episodes: list[Episode], half: int) -> dict[int, np.ndarray]:
    """Samples within the velocity-fit span of an impact (with a static or between bodies), or
    before the first full span, per episode index."""
    out = {}
    for i, e in enumerate(episodes):
        impact = (frame_labels(scene, e) == "impact").any(axis=1) | near_contact(scene, e)  # (T,)
        bad = np.convolve(impact.astype(float), np.ones(2 * half + 3), mode="same") > 0
        bad[:half] = True  # a one-sided velocity fit at the episode start is several times noisier
        out[i] = bad
    return out


def _all_labels(scene: SceneSpec, episodes: list[Episode]) -> set[str]:
    return {str(v) for e in episodes for v in np.unique(frame_labels(scene, e).astype(str))}


def _candidates(names: list[str], scene: SceneSpec) -> dict[str, Effect]:
    out: dict[str, Effect] = {}
    for name in names:
        cls = EFFECTS.get(name)
        if name == "none" or not cls().applies(scene):
            continue
        if getattr(cls, "per_body", False) and len(scene.bodies) > 1:
            for b in scene.names:
                out[f"{name}[{b}]"] = cls(bodies=(b,))
        else:
            out[name] = cls()
    return out


def _subsample(windows: list[Window], budget: float, length: float, rng: np.random.Generator) -> list[Window]:
    k = max(1, int(budget // length))
    if len(windows) <= k:
        return windows
    idx = np.sort(rng.choice(len(windows), size=k, replace=False))
    return [windows[i] for i in idx]
