"""Run one deterministic computation in a forked process while this process does other work.

Why: after the search, the finder's last stages ran one after the other in the main process
while the fitting workers sat idle (about 2 s of ``bench/gap_speed.py``'s 22 s on 2 cores): the
check bounds the model (a parametric bootstrap, ``voe.gap.check``), then the drift step tests the
same model's parameters for a change in time (``voe.gap.drift``). The drift test depends only on
the model, which the check leaves as it is unless it drops a part, so it can be computed for the
search's model on the second core while the check runs, and used when the check kept that model
(the same effect and parameters to the bit); otherwise it is computed again, as before. The
answer is the same either way: the forked process runs the same function on the same inputs
(``voe.parallel``'s contract, written for its ``parallel_map``).

``Ahead`` is that one forked call. With ``n_jobs`` 1 it runs nothing ahead and ``result`` computes
in this process. With ``idle=True`` the forked process runs at the lowest priority (nice 19), so
it takes only CPU time the fitting workers leave unused: work started on a guess
(``voe.gap.speculate``) then costs the search nothing when the guess is wrong, and ``promote``
gives it this process's priority back once its result is needed.
"""

from __future__ import annotations

import multiprocessing as mp
import os
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Generic, TypeVar

from voe.parallel import release_signals, signals_held, stop_workers

R = TypeVar("R")

_PENDING: dict[int, Callable[[], object]] = {}  # token -> call, inherited by the forked process


def _call(token: int) -> object:
    return _PENDING[token]()


IDLE_NICE = 19  # the lowest priority: such a process runs on cores the others leave idle


def _release_signals_idle() -> None:
    release_signals()
    if hasattr(os, "setpriority"):
        os.setpriority(os.PRIO_PROCESS, 0, IDLE_NICE)


class Ahead(Generic[R]):
    """``fn()`` started now in one forked process (``n_jobs > 1`` and fork available), else later.

    Use as a context manager, so the process is stopped if the caller fails before ``result``.

    Args:
        fn: deterministic, no arguments; its result is pickled back (keep it small).
        n_jobs: processes the caller may use; ahead only if more than one.
        counted: objects with an ``n_rollouts`` count (``voe.gap.shooting.Shooter``) that ``fn``
            may raise; what it adds in the forked process is added to them here, as if ``fn`` had
            run in this process (the bench reports the count).
    """

    def __init__(self, fn: Callable[[], R], n_jobs: int, counted: tuple = (), idle: bool = False) -> None:
        self.fn, self.counted = fn, counted
        self._pool: ProcessPoolExecutor | None = None
        self._future: Future | None = None
        if n_jobs > 1 and "fork" in mp.get_all_start_methods():
            token = id(self)
            _PENDING[token] = self._counting  # before the fork, so the process has it
            self._token = token
            self._pool = ProcessPoolExecutor(max_workers=1, mp_context=mp.get_context("fork"),
                                             initializer=_release_signals_idle if idle else release_signals)
            with signals_held():  # submit forks the process
                self._future = self._pool.submit(_call, token)

    def _counting(self) -> tuple[R, list[int]]:
        before = [c.n_rollouts for c in self.counted]
        out = self.fn()
        return out, [c.n_rollouts - b for c, b in zip(self.counted, before, strict=True)]

    @property
    def forked(self) -> bool:
        """Whether ``fn`` runs in a forked process (its side effects stay in that process)."""
        return self._future is not None

    def promote(self) -> bool:
        """Give the forked process this process's priority (after ``idle=True``); whether it now
        runs at that priority or has finished. False where lowering a nice value is not
        permitted (not root, ``RLIMIT_NICE`` 0): the caller may then rather compute itself."""
        if self._future is None or self._future.done():
            return self._future is not None
        try:
            mine = os.getpriority(os.PRIO_PROCESS, 0)
            for pid in list(getattr(self._pool, "_processes", None) or {}):
                os.setpriority(os.PRIO_PROCESS, pid, mine)
        except (OSError, AttributeError):
            return self._future.done()
        return True

    def result(self) -> R:
        """``fn()``: from the forked process if it was started, else computed now."""
        if self._future is None:
            return self.fn()
        try:
            out, added = self._future.result()
        finally:
            self.close()
        for c, n in zip(self.counted, added, strict=True):
            c.n_rollouts += n
        return out

    def cancel(self) -> None:
        """The result is not needed: stop the forked process now instead of waiting for it."""
        if self._pool is not None:
            stop_workers(self._pool)
        self.close()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            _PENDING.pop(self._token, None)
            self._pool, self._future = None, None

    def __enter__(self) -> Ahead[R]:
        return self

    def __exit__(self, *exc: object) -> None:
        if self._pool is not None:
            self.cancel()
