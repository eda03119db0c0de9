"""The checks of a model that may be final, started while the search goes on.

Why: after the search, the check bounds the model (``voe.gap.check.model_intervals``, about
1.6 CPU-s on ``bench/gap_speed.py``'s case, in the main process) and the drift step tests it
(``voe.gap.drift.drift_found``, about 2 CPU-s, on the second core: ``DriftAhead``). Both need only
the model. The search's model is the last one it accepted, and it is known before the search
ends: on that case the first round accepts ``quadratic_drag``, and round 2 (13 fits) and the
pair step (3 joint fits, whose training costs are ranked in the main process first) only
confirm that nothing more passes. Those stages leave a core idle for about 2 CPU-s in all (the
end of a round's loop, the ranking, the third of three pair fits on two workers).

So each time the search accepts a model (``voe.gap.greedy``'s ``on_model``), both checks of that
model are started in forked processes at the lowest priority (``voe.gap.parallel.Ahead`` with
``idle=True``): they run on what the fitting workers leave idle and cost the search nothing when a
later round replaces the model (they are then stopped). When the check asks for a model's
interval or drift, a result is taken from here only for the same effect and parameters to the
bit (the forked process runs the same function on the same inputs, so the answer is the same) and
only if it is finished or its process could be given normal priority back; otherwise it is
stopped and the check computes as before. With ``n_jobs`` 1 nothing is started.
"""

from __future__ import annotations

import numpy as np

from voe.gap.check import model_intervals
from voe.gap.drift import drift_found
from voe.gap.fit import FitResult, effect_key
from voe.gap.parallel import Ahead
from voe.gap.stages import GapConfig, Problem, fit_context


def model_key(model: FitResult) -> tuple:
    """What the checks read of a model: its effect (parts and their form) and parameters, to the bit."""
    return type(model.effect).__qualname__, effect_key(model.effect), model.params.tobytes()


class Speculation:
    """The interval and drift checks of the search's latest model, running ahead at idle priority.

    Use as a context manager, so the processes are stopped if the caller fails.
    """

    def __init__(self, p: Problem, config: GapConfig, seed: int, n_jobs: int) -> None:
        self.p, self.config, self.seed, self.n_jobs = p, config, seed, n_jobs
        self.key: tuple | None = None
        self._aheads: dict[str, Ahead] = {}

    def start(self, model: FitResult) -> None:
        """Start both checks of ``model`` (stopping those of an earlier model)."""
        self.stop()
        if self.n_jobs <= 1:
            return
        p, config, seed = self.p, self.config, self.seed
        self.key = model_key(model)

        def intervals() -> tuple[np.ndarray, np.ndarray]:
            return model_intervals(p, p.split.fit, model, fit_context(p), config, seed)

        self._aheads = {"intervals": Ahead(intervals, self.n_jobs, (p.shooter,), idle=True),
                        "drift": Ahead(lambda: drift_found(p, model, config, seed), self.n_jobs, (p.shooter,),
                                       idle=True)}

    def take(self, what: str, model: FitResult) -> Ahead | None:
        """The running ``what`` (``"intervals"`` or ``"drift"``) of ``model``, now at normal
        priority, if it was started for this model and can finish as fast as a fresh start; the
        caller owns it (``result``). Else None (anything started is stopped)."""
        ahead = self._aheads.pop(what, None)
        if ahead is None:
            return None
        if self.key != model_key(model) or not ahead.promote():
            ahead.cancel()
            return None
        return ahead

    def intervals(self, model: FitResult) -> tuple[np.ndarray, np.ndarray] | None:
        """``model_intervals`` of ``model`` from the process started ahead, or None."""
        ahead = self.take("intervals", model)
        return None if ahead is None else ahead.result()

    def stop(self) -> None:
        for ahead in self._aheads.values():
            ahead.cancel()
        self._aheads, self.key = {}, None

    def __enter__(self) -> Speculation:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
