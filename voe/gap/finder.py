"""``GapFinder``: locate, hypothesise, fit and verify, in scikit-learn style.

Why: one estimator object keeps the pipeline's choices (effects, budget, seed) in its constructor
and its findings in attributes ending in ``_``, so notebooks, the CLI and the bench drive the same
code. Episodes are split chronologically: the last third is held out, the rest trains.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from voe.gap.context import frame_labels
from voe.gap.effects import EFFECTS
from voe.gap.effects.base import Effect, EffectSum, FitContext
from voe.gap.fit import FitConfig, Fitter
from voe.gap.locate import locate, window_z
from voe.gap.prefit import flight_samples
from voe.gap.recordings import Episode, load_recordings
from voe.gap.scene import load_scene, resolve_joints
from voe.gap.search import candidate_gains, greedy, null_threshold
from voe.gap.shooting import Shooter, Window, choose_half, make_windows, noise_floor
from voe.gap.synth import null_like
from voe.gap.verify import explain, verify
from voe.sim.scenefile import SceneSpec

ALL_EFFECTS = tuple(n for n in EFFECTS.ids() if n != "none")


@dataclass(frozen=True)
class GapConfig:
    """Knobs of the search. Budgets are simulated seconds per evaluation (windows subsampled)."""

    fit_window: float = 1.0
    locate_window: float = 1.0
    substep: float | None = None  # default 1 ms, 0.5 ms for scenes with joints
    fit_budget: float = 8.0
    test_budget: float = 20.0  # held-out windows are simulated once per candidate: cheap, and many steady the gain
    null_budget: float = 6.0
    min_gain: float = 0.05  # practical floor: a held-out gain (search.window_gain) below 5 % is never accepted
    null_alpha: float = 0.05  # the threshold is the null's best gain at this upper quantile
    gain_lower_q: float | None = 0.05  # the gain's bootstrap quantile over held-out windows must be > 0
    z_min: float = 5.0
    fit: FitConfig = FitConfig()


class GapFinder:
    """Find what a nominal pymunk scene leaves out, from recordings.

    Args:
        effects: effect names to consider (default: the whole library but ``none``).
        max_effects: at most this many effects are accepted (greedy).
        seed: seeds null-data noise and window subsampling.
        config: search settings.
        n_jobs: processes that fit candidates in parallel (results do not depend on it).
    """

    def __init__(self, effects: tuple[str, ...] | list[str] | None = None, max_effects: int = 3, seed: int = 0,
                 config: GapConfig | None = None, n_jobs: int = 1) -> None:
        self.effects = tuple(effects) if effects else ALL_EFFECTS
        self.max_effects = max_effects
        self.seed = seed
        self.config = config or GapConfig()
        self.n_jobs = n_jobs

    # ------------------------------------------------------------------------------------------
    def fit(self, scene: str | Path | SceneSpec, recordings: str | Path | pd.DataFrame | list[Episode],
            progress: Callable[[str], None] | None = None) -> GapFinder:
        """Run the whole diagnosis. Returns self; results are in the ``*_`` attributes."""
        note = progress or (lambda s: None)
        names = [EFFECTS.resolve(n) for n in self.effects]  # fail fast on typos
        self.scene_, self.episodes_ = _load(scene, recordings)
        cfg, rng = self.config, np.random.default_rng(self.seed)
        sub = cfg.substep or (5e-4 if self.scene_.joints else 1e-3)
        self.substep_ = sub
        self.sigma_ = noise_floor(self.episodes_)  # (B, 3)
        n = len(self.episodes_)
        n_test = max(1, int(np.ceil(n / 3))) if n > 1 else 0
        train_ids, test_ids = list(range(n - n_test)) or [0], list(range(n - n_test, n)) or [0]
        self.train_episodes_ = [self.episodes_[i].id for i in train_ids]
        self.holdout_episodes_ = [self.episodes_[i].id for i in test_ids]
        ctx = _context(self.scene_, self.episodes_)
        candidates = _candidates(names, self.scene_)

        # 1. null calibration on simulated clean data
        note("null: simulate clean data")
        loc_all = make_windows(self.episodes_, list(range(n)), cfg.locate_window)
        self.half_ = choose_half(self.scene_, self.episodes_, loc_all, sub)
        self._bad = _bad_starts(self.scene_, self.episodes_, self.half_)
        loc_all = make_windows(self.episodes_, list(range(n)), cfg.locate_window, bad_start=self._bad)
        null_eps = null_like(self.scene_, self.episodes_, self.sigma_, rng, sub)
        null_shooter = Shooter(self.scene_, null_eps, sub, self.half_)
        z_null = window_z(null_shooter, loc_all, self.sigma_).max(axis=(1, 2))  # (W,)
        self.z_threshold_ = float(max(cfg.z_min, np.quantile(z_null, 0.95)))
        self.z_strong_ = float(max(cfg.z_min, np.max(z_null)))
        null_ctx = replace(ctx, flight=flight_samples(self.scene_, null_eps))  # the null's own starts
        # held-out windows overlap by half (a collision just after a window boundary is still
        # seen from a start before it) and are the same windows for the null and the data (the
        # spread of a geometric mean over the null's 6 windows once set a threshold the data's
        # 10 windows could not reach)
        w = cfg.fit_window
        test_w = _subsample(make_windows(self.episodes_, test_ids, w, stride=w / 2, bad_start=self._bad),
                            cfg.test_budget, w, rng)
        nf = Fitter(null_shooter, self.sigma_, self._train(null_eps, train_ids, rng, cfg.null_budget), test_w,
                    null_ctx, cfg.fit, pool=self._pool(null_eps, train_ids))
        null_before = nf.heldout_sse(None, None)
        null_results, null_gains = candidate_gains(nf, candidates, None, np.zeros(0), null_before,
                                                   lambda k: note(f"null: {k}"), self.n_jobs)
        self.null_gains_ = {k: round(v, 4) for k, v in null_gains.items() if np.isfinite(v)}
        q, self.null_best_ = null_threshold(null_before, null_results, cfg.null_alpha, self.seed)
        self.threshold_ = float(max(cfg.min_gain, q, max(null_gains.values(), default=0.0)))

        # 2. locate
        note("locate")
        shooter = Shooter(self.scene_, self.episodes_, sub, self.half_)
        z = window_z(shooter, loc_all, self.sigma_)
        self.located_ = [x.to_dict() for x in locate(shooter, loc_all, z, self.z_threshold_)]
        self._shooter, self._loc_windows, self._test_ids = shooter, loc_all, test_ids
        contexts = {x["context"] for x in self.located_} or _all_labels(self.scene_, self.episodes_)

        # 3. hypothesise and fit
        train_w = self._train(self.episodes_, train_ids, rng, cfg.fit_budget)
        fitter = Fitter(shooter, self.sigma_, train_w, test_w, ctx, cfg.fit,
                        pool=self._pool(self.episodes_, train_ids))
        effect, params, self.rounds_ = greedy(fitter, candidates, self.threshold_, self.max_effects, contexts,
                                              lambda k: note(f"fit: {k}"), cfg.gain_lower_q, self.n_jobs)
        self.effect_, self.params_ = effect, params
        self.groups_ = [r.group for r in self.rounds_ if r.winner]
        self.effects_ = _effect_dicts(effect, params, self.scene_)

        # 4. verify on all held-out windows
        note("verify")
        hold = make_windows(self.episodes_, test_ids, cfg.fit_window, bad_start=self._bad)
        self.verification_ = verify(shooter, hold, effect, params, self.sigma_, self.z_threshold_)
        v = self.verification_
        self.fit_ = {"metric": "rmse_m (x, y and angle*sqrt(I/m), multiple shooting windows of "
                               f"{cfg.fit_window:g} s)",
                     "before": v.rmse_before, "after": v.rmse_after,
                     "position_before": v.position_rmse_before, "position_after": v.position_rmse_after,
                     "window_median_before": v.window_median_before, "window_median_after": v.window_median_after,
                     "holdout_episodes": self.holdout_episodes_, "train_episodes": self.train_episodes_,
                     "threshold_gain": self.threshold_, "z_threshold": self.z_threshold_,
                     "residuals_look_like_noise": v.looks_like_noise,
                     "median_z_before": v.median_z_before, "median_z_after": v.median_z_after}
        strong = [x for x in self.located_ if x["z"] > self.z_strong_]
        self.verdict_ = "mismatch" if (self.effects_ or strong) else "consistent"
        self.explanation_ = explain(self.effects_, self.groups_, self.located_, v, self.threshold_,
                                    self.sigma_, self.holdout_episodes_)
        return self

    def _train(self, episodes: list[Episode], train_ids: list[int], rng: np.random.Generator,
               budget: float) -> list[Window]:
        w = self.config.fit_window
        return _subsample(make_windows(episodes, train_ids, w, bad_start=self._bad), budget, w, rng)

    def _pool(self, episodes: list[Episode], train_ids: list[int]) -> list[Window]:
        """Training windows at half-window strides, for sparse effects (``Fitter.focused``).

        Why: a window cannot start within the velocity-fit span of an impact, so back-to-back
        windows skip every collision that falls just after a window boundary (five of eight
        ball-box strikes in one bench case). Half-overlapping windows cover each collision from
        a start before it.
        """
        w = self.config.fit_window
        return make_windows(episodes, train_ids, w, stride=w / 2, bad_start=self._bad)

    def to_dict(self) -> dict:
        """The diagnosis as plain JSON-ready data (without provenance)."""
        return {"verdict": self.verdict_, "located": self.located_, "effects": self.effects_, "fit": self.fit_,
                "explanation": self.explanation_, "groups": self.groups_,
                "null": {"gains": self.null_gains_, "threshold_gain": self.threshold_, "z_threshold": self.z_threshold_,
                         "z_max": self.z_strong_, "alpha": self.config.null_alpha,
                         "best_gain_quantiles": {str(q): float(np.quantile(self.null_best_, q)) if self.null_best_.size
                                                 else None for q in (0.5, 0.95, 0.99)}},
                "rounds": [{"before": r.before, "winner": r.winner, "group": r.group,
                            "gains": {k: (round(g, 4) if np.isfinite(g) else None) for k, g in r.gains.items()}}
                           for r in self.rounds_],
                "noise_floor": {n: dict(zip(("x", "y", "angle"), map(float, s), strict=True))
                                for n, s in zip(self.scene_.names, self.sigma_, strict=True)}}


def _load(scene: str | Path | SceneSpec, recordings: str | Path | pd.DataFrame | list[Episode]) -> tuple[SceneSpec, list[Episode]]:
    if isinstance(scene, SceneSpec):
        spec, joints = scene, None
    else:
        spec, joints, _ = load_scene(scene)
    if isinstance(recordings, list):
        eps = recordings
    elif isinstance(recordings, pd.DataFrame):
        eps = load_recordings("<dataframe>", spec, recordings)
    else:
        eps = load_recordings(recordings, spec)
    if joints:
        spec = resolve_joints(spec, joints, eps[0].pose[0])
    return spec, eps


def _bad_starts(scene: SceneSpec, episodes: list[Episode], half: int) -> dict[int, np.ndarray]:
    """Samples within the velocity-fit span of an impact of any body, or before the first full
    span, per episode index."""
    out = {}
    for i, e in enumerate(episodes):
        impact = (frame_labels(scene, e) == "impact").any(axis=1).astype(float)  # (T,)
        bad = np.convolve(impact, np.ones(2 * half + 3), mode="same") > 0
        bad[:half] = True  # a one-sided velocity fit at the episode start is several times noisier
        out[i] = bad
    return out


def _all_labels(scene: SceneSpec, episodes: list[Episode]) -> set[str]:
    return {str(v) for e in episodes for v in np.unique(frame_labels(scene, e).astype(str))}


def _context(scene: SceneSpec, episodes: list[Episode]) -> FitContext:
    pos = np.concatenate([e.pose[:, :, :2].reshape(-1, 2) for e in episodes])
    vel = np.concatenate([np.diff(e.pose, axis=0).reshape(-1, 3) / np.median(np.diff(e.t)) for e in episodes])
    return FitContext(scene, pos.min(axis=0), pos.max(axis=0),
                      float(np.median(np.linalg.norm(vel[:, :2], axis=1))), float(np.median(np.abs(vel[:, 2]))),
                      flight_samples(scene, episodes))


def _candidates(names: list[str], scene: SceneSpec) -> dict[str, Effect]:
    out: dict[str, Effect] = {}
    for name in names:
        cls = EFFECTS.get(name)
        if name == "none":
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


def _effect_dicts(effect: Effect | None, params: np.ndarray, scene: SceneSpec) -> list[dict]:
    if effect is None:
        return []
    parts = effect.parts
    split = effect.split(params) if isinstance(effect, EffectSum) else [params]
    return [{"name": e.name, "params": {n: float(v) for n, v in zip(e.param_names, p, strict=True)},
             "units": dict(zip(e.param_names, e.units, strict=True)),
             "bodies": list(e.bodies) if e.bodies else scene.names, "summary": e.summary}
            for e, p in zip(parts, split, strict=True)]
