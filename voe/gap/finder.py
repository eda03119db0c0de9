"""``GapFinder``: locate, search, check, in scikit-learn style.

Why: one estimator object keeps the pipeline's choices (effects, budget, seed) in its constructor
and its findings in attributes ending in ``_``, so notebooks, the CLI and the bench drive the same
code. ``fit`` only chains the stages (``voe.gap.stages``, ``voe.gap.check``), each of which
returns a frozen result; the ``*_`` attributes are read from those results.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np
import pandas as pd

from voe.gap.carry_over import short_on_test, worse_on_test
from voe.gap.check import Checked, check_step, effect_dicts
from voe.gap.departure import ALPHA
from voe.gap.drift import DriftAhead, drift_step
from voe.gap.effects import EFFECTS
from voe.gap.locate import LOCAL, by_bar
from voe.gap.parallel import Ahead
from voe.gap.recordings import Episode
from voe.gap.speculate import Speculation
from voe.gap.stages import (
    GapConfig,
    Location,
    PendingLocation,
    Problem,
    Search,
    locate_parts,
    prepare,
    search_step,
)
from voe.gap.verify import explain
from voe.sim.scenefile import SceneSpec

ALL_EFFECTS = tuple(n for n in EFFECTS.ids() if n != "none")

__all__ = ["ALL_EFFECTS", "GapConfig", "GapFinder"]


def unnamed_verdict(located: list[dict], departure_p: float) -> str:
    """The verdict when no effect is named: ``unexplained`` when stretches are located and either
    one is wild (infinite z) or the data depart as a whole (``departure_p`` below ALPHA: many
    windows, not one chaotic one; ``voe.gap.departure``), else ``consistent``."""
    wild = any(not np.isfinite(x["z"]) for x in located)
    return "unexplained" if located and (wild or departure_p < ALPHA) else "consistent"


def _per_body(names: tuple[str, ...] | list[str], values: np.ndarray) -> dict:
    """(B, 3) per-body x, y, angle values as gap.json's ``{body: {x, y, angle}}``."""
    return {n: dict(zip(("x", "y", "angle"), map(float, v), strict=True)) for n, v in zip(names, values, strict=True)}


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

    def fit(self, scene: str | Path | SceneSpec, recordings: str | Path | pd.DataFrame | list[Episode],
            progress: Callable[[str], None] | None = None, total: Callable[[int], None] | None = None) -> GapFinder:
        """Run the whole diagnosis. Returns self; results are in the ``*_`` attributes.

        ``progress`` is called once per step; ``total``, if given, once with the most steps
        there can be (known once the candidates are), so that a progress bar can show an ETA.
        """
        note = progress or (lambda s: None)
        self.first_look_: dict | None = None
        steps = self._look(scene, recordings, self.config, note, total)
        if self.config.second_look and not self.effects_ and self.problem_.split.scheme == "three-way":
            # the three-way split named nothing: a truth felt in few windows (a box's mass in its
            # collisions, a rolling resistance while the ball rolls) may have had too few selection
            # windows to pass the bootstrap; cross-fitted, every non-test episode selects. Only a
            # look that named nothing is repeated, so an effect the first look named never changes,
            # and a false name needs either look to give one: the false-discovery rate is at most
            # the sum of the two looks' (the bench measures it with the second look on).
            self.first_look_ = {"scheme": self.problem_.split.scheme, "verdict": self.verdict_,
                                "located": len(self.located_), "dropped": [d["effect"] for d in self.checked_.dropped],
                                "departure_p": self.location_.departure_p}
            note("second look: cross-fitting")
            second = replace(self.config, cross_fit=True)
            self._look(scene, recordings, second, note, None if total is None else (lambda n: total(steps + 1 + n)))
            self.checked_ = short_on_test(self.checked_, self.problem_, second, self.location_.z_threshold)
        return self

    def _look(self, scene, recordings, config: GapConfig, note: Callable[[str], None],
              total: Callable[[int], None] | None) -> int:
        """One whole diagnosis under ``config``, into the ``*_`` attributes; returns its most steps."""
        rng = np.random.default_rng(self.seed)
        self.problem_: Problem = prepare(scene, recordings, self.effects, config)
        n = len(self.problem_.candidates)
        steps = 3 + 2 * sum(n - r for r in range(min(self.max_effects, n)))
        if total is not None:  # locate, check, drift, and each round's candidates on the data and the null
            total(steps)
        note("locate")
        null_eps, finish = locate_parts(self.problem_, config, rng)
        # the location but its clean replicate (window z-scores, located stretches, the departure
        # test) runs on a second process while the search starts (voe.gap.parallel.Ahead; rng is
        # not used after it); the checks of each model the search accepts start at idle priority
        # while it goes on (voe.gap.speculate), used only for the model the search ends with
        with Speculation(self.problem_, config, self.seed, self.n_jobs) as spec:
            with Ahead(finish, self.n_jobs, (self.problem_.shooter,)) as ahead:
                location = functools.cache(ahead.result)  # asked by a tie and at the end; computed once
                self.search_: Search = search_step(self.problem_, PendingLocation(null_eps, location), config,
                                                   self.max_effects, self.seed, self.n_jobs, note, spec.start)
                self.location_: Location = location()
            note("check")
            # the drift test of the search's model runs on a second process while the check runs
            # (voe.gap.drift.DriftAhead); used only if the check keeps that model
            model = self.search_.result.model
            started = spec.take("drift", model) if model is not None else None
            with DriftAhead(self.problem_, model, config, self.seed, self.n_jobs, started) as ahead:
                checked = check_step(self.problem_, self.location_, self.search_, config, self.seed,
                                     spec.intervals)
                note("drift")
                checked = drift_step(self.problem_, self.location_, self.search_, checked, config, self.seed,
                                     ahead)
                # the final model's test figures: it must not leave the typical test window departing more
                self.checked_: Checked = worse_on_test(checked, self.problem_, config, self.location_.z_threshold,
                                                       self.location_.null_episodes, self.seed)
        return steps

    # --- findings, read from the stage results ----------------------------------------------
    @property
    def scene_(self) -> SceneSpec:
        return self.problem_.scene

    @property
    def episodes_(self) -> list[Episode]:
        return self.problem_.episodes

    @property
    def located_(self) -> list[dict]:
        return self.location_.located

    @property
    def z_threshold_(self) -> float:
        return self.location_.z_threshold

    @property
    def z_strong_(self) -> float:
        return self.location_.z_strong

    @property
    def rounds_(self) -> tuple:
        return self.search_.result.rounds

    @property
    def groups_(self) -> list[list[str]]:
        return [list(r.group) for r in self._kept_rounds()]

    def _kept_rounds(self) -> list:
        kept = set(self.checked_.keys)
        return [r for r in self.search_.result.rounds if r.winner and r.winner in kept]

    @property
    def threshold_(self) -> float:
        return self.search_.null[0].threshold if self.search_.null else self.config.min_gain

    @property
    def null_gains_(self) -> dict[str, float]:
        return {k: round(v, 4) for k, v in self.search_.null[0].gains.items() if np.isfinite(v)} if self.search_.null else {}

    @property
    def effect_(self):
        m = self.checked_.model
        return m.effect if m is not None else None

    @property
    def params_(self) -> np.ndarray:
        m = self.checked_.model
        return m.params if m is not None else np.zeros(0)

    @property
    def effects_(self) -> list[dict]:
        return effect_dicts(self.checked_, self.problem_)

    @property
    def verdict_(self) -> str:
        if self.effects_:
            return "mismatch"
        return unnamed_verdict(self.located_, self.location_.departure_p)

    @property
    def fit_(self) -> dict:
        v, split = self.checked_.verification, self.problem_.split
        ids = [e.id for e in self.episodes_]
        return {"metric": "rmse_m (x, y and angle*sqrt(I/m), multiple shooting windows of "
                          f"{self.config.fit_window:g} s)", "on": self.checked_.test_note,
                "before": v.rmse_before, "after": v.rmse_after,
                "position_before": v.position_rmse_before, "position_after": v.position_rmse_after,
                "window_median_before": v.window_median_before, "window_median_after": v.window_median_after,
                "test_episodes": [ids[i] for i in split.test] if not split.cross_validated else ids,
                "threshold_gain": self.threshold_, "z_threshold": self.z_threshold_,
                "residuals_look_like_noise": v.looks_like_noise,
                "median_z_before": v.median_z_before, "median_z_after": v.median_z_after,
                "departure_p": self.location_.departure_p}

    def _z_bar(self) -> float:
        """The z the explanation lists stretches above: the clean replicate's largest window z, or
        its 95th percentile when no located stretch exceeds the largest (an unexplained verdict
        then rests on the paired test over all windows) or the stretches were located against
        their windows' own replicates (the bar they did not pass: ``voe.gap.stages.locate_parts``)."""
        local = bool(by_bar(self.located_, LOCAL))
        if self.verdict_ == "unexplained" and (local or not any(not x["z"] <= self.z_strong_ for x in self.located_)):
            return self.z_threshold_
        return self.z_strong_

    @property
    def explanation_(self) -> str:
        r0 = self.rounds_[0] if self.rounds_ else None
        best = max(r0.gains.items(), key=lambda kv: kv[1]) if r0 and r0.gains else None
        text = explain(self.verdict_, self.effects_, self.groups_, self.located_, self.checked_.verification,
                       self.threshold_, self.problem_.sigma, self.checked_.test_note, self._z_bar(),
                       self.checked_.dropped, best, [r.tie for r in self._kept_rounds()],
                       self.location_.departure_p, self.config.z_min)
        if self.first_look_ is not None:
            first = self.first_look_
            text += (f" (Second look: the three-way split named nothing (verdict {first['verdict']}), so the finder "
                     "looked again with cross-fitting, every non-test episode selecting; this is that look's answer. "
                     "A name needs either look to give one, so the false-discovery rate is at most the sum of the "
                     "two looks'.)")
        return text

    def to_dict(self) -> dict:
        """The diagnosis as plain JSON-ready data (without provenance)."""
        return {"verdict": self.verdict_, "located": self.located_, "effects": self.effects_, "fit": self.fit_,
                "explanation": self.explanation_, "groups": self.groups_,
                "episodes": self.problem_.split.roles(self.episodes_),
                "dropped": list(self.checked_.dropped),
                "second_look": self.first_look_,  # None, or what the three-way look that named nothing said
                "outliers": [asdict(o) for e in self.episodes_ for o in e.outliers],  # kept when loaded with "flag"
                "null": {"z_threshold": self.z_threshold_, "z_max": self.z_strong_, "alpha": self.config.null_alpha,
                         "rounds": [r.to_dict() for r in self.search_.null]},
                "rounds": [r.to_dict() for r in self.rounds_],
                "noise_floor": _per_body(self.scene_.names, self.problem_.sigma),
                "noise_ar1": _per_body(self.scene_.names, self.problem_.phi),
                "timing_jitter": None if (j := self.problem_.jitter) is None else
                {"seconds": j.seconds, "sensor_noise": _per_body(self.scene_.names, j.sensor)}}
