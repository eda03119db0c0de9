"""The one "serial or a process pool" loop of voe: ``parallel_map``.

Why one: probe generation, world generation, validity controls, the gap finder and its bench,
and the demo all map a deterministic function over independent items. Each used to carry its own
copy of the loop (``Pool.imap`` here, ``as_completed`` there), with different ordering, error and
memory behaviour. Here the contract is written once:

* results come back **in input order**, so whatever ``jobs`` is the caller sees the same
  sequence and writes byte-identical output;
* it is a **lazy iterator** that keeps at most a few items per worker in flight, so a caller that
  streams results to disk (world generation, 100k clips) holds a bounded number of them;
* a worker's exception is **re-raised in the caller with its type**, the worker's traceback as
  its cause and a note naming the item, so a ``VoeError`` still ends as one line on the CLI;
* with the ``fork`` start method (Linux, macOS on request) ``fn`` is inherited by the workers,
  not pickled, so it may be a closure over unpicklable state (pymunk spaces in the gap finder).
  Items and results are pickled and should be small.
"""

from __future__ import annotations

import contextlib
import itertools
import multiprocessing as mp
import signal
import threading
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any, TypeVar

from voe.errors import VoeError

T = TypeVar("T")
R = TypeVar("R")

_FNS: dict[int, Callable[[Any], Any]] = {}  # token -> fn, inherited by forked workers
_TOKENS = itertools.count()


def _call_forked(token: int, item: Any) -> Any:
    return _FNS[token](item)


def _note(exc: BaseException, index: int, item: Any, fn: Callable) -> None:
    text = repr(item)
    text = text if len(text) <= 200 else text[:197] + "..."
    exc.add_note(f"(parallel_map: {getattr(fn, '__qualname__', fn)!s} failed on item {index}: {text})")


_HELD = {signal.SIGINT, signal.SIGTERM}


@contextlib.contextmanager
def signals_held():
    """Hold SIGINT and SIGTERM while a worker may be forked; they are delivered on release.

    Why: a signal that arrives just after a fork runs its handler inside the at-fork callbacks
    (logging's ``_releaseLock``), where Python prints "Exception ignored" and drops the handler's
    ``KeyboardInterrupt``: the command then ran on to its end although told to stop (seen in
    CI). Held here, it is delivered at the ``with``'s end, in ordinary code.
    """
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield  # not on Windows (no fork there either); handlers can only be swapped in the main thread
        return
    # The mask covers this thread only: with other threads alive (a progress bar's monitor, the
    # pool's manager) the kernel hands the signal to one of them and Python still runs the handler
    # here, at-fork callbacks included. So the handlers are swapped for a recorder too, and what
    # it recorded is raised again, under the real handlers, once the fork is over.
    arrived: list[int] = []
    saved = {s: signal.signal(s, lambda signum, _frame: arrived.append(signum)) for s in _HELD}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)  # a signal held by the mask lands in the recorder
        for s, h in saved.items():
            if h is not None:  # None: a handler installed from C, which Python cannot restore
                signal.signal(s, h)
        for s in dict.fromkeys(arrived):
            signal.raise_signal(s)


def release_signals() -> None:
    """Worker initializer: a forked worker inherits the held mask and the parent's handlers.

    Why both: it must answer signals (the parent stops its workers with SIGTERM when it is
    interrupted), and answer them by ending quietly: an inherited ``voe.cli.main`` handler
    would raise ``Interrupted`` inside the worker's queue read and print a traceback under the
    parent's one-line message (seen in ``tests/reliability/test_kill.py``). Ctrl-C reaches the
    whole process group; the parent alone handles it and stops the workers.
    """
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _HELD)


def parallel_map(fn: Callable[[T], R], items: Iterable[T], jobs: int = 1,
                 progress: Callable[[int], None] | None = None, ahead: int = 4,
                 start_method: str | None = None) -> Iterator[R]:
    """``map(fn, items)`` in ``jobs`` processes, yielding results in input order.

    Args:
        fn: a deterministic function of one item. With ``fork`` it may be any callable; with
            ``spawn`` it must be importable (module level).
        items: consumed lazily; at most ``ahead * jobs`` of them are submitted beyond the result
            the caller is waiting for.
        jobs: processes; 1 (or less) runs in this process, with no pool at all.
        progress: called with 1 after each result is yielded (e.g. ``voe.progress.progress``'s tick).
        ahead: items in flight per worker (bounds memory when results are large).
        start_method: ``fork`` (the default where available) or ``spawn``; a method this
            platform lacks runs serially (a closure cannot be sent to spawned workers).

    Raises:
        The first failing item's exception (its own type), after the pool is shut down.
    """
    if hasattr(items, "__len__"):
        jobs = min(jobs, len(items))  # no idle workers
    method = start_method or ("fork" if "fork" in mp.get_all_start_methods() else "spawn")
    if jobs <= 1 or method not in mp.get_all_start_methods():  # same results, by contract
        yield from _serial(fn, items, progress)
        return
    token = next(_TOKENS)
    forked = method == "fork"
    if forked:
        _FNS[token] = fn  # before the pool exists, so every forked worker has it
    pending: deque[tuple[int, Any, Future]] = deque()
    it = iter(enumerate(items))
    pool = ProcessPoolExecutor(max_workers=jobs, mp_context=mp.get_context(method), initializer=release_signals)
    try:
        def submit() -> bool:
            nxt = next(it, None)
            if nxt is None:
                return False
            i, item = nxt
            with signals_held():  # submit may fork a worker
                fut = pool.submit(_call_forked, token, item) if forked else pool.submit(fn, item)
            pending.append((i, item, fut))
            return True

        for _ in range(max(1, ahead) * jobs):
            if not submit():
                break
        while pending:
            i, item, fut = pending.popleft()
            try:
                result = fut.result()
            except BrokenProcessPool as exc:
                raise VoeError(f"a worker process died while running {getattr(fn, '__qualname__', fn)} on "
                               f"item {i} (out of memory or killed?); retry with --jobs 1 to see why") from exc
            except BaseException as exc:
                _note(exc, i, item, fn)
                raise
            submit()
            yield result
            if progress:
                progress(1)
    except KeyboardInterrupt:  # Ctrl-C or SIGTERM (voe.cli.main) sent to this process alone:
        stop_workers(pool)  # now, instead of waiting out their items
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        _FNS.pop(token, None)


def stop_workers(pool: ProcessPoolExecutor) -> None:
    """Terminate the pool's workers, reap them, and unblock the pool's reader of their results.

    Why the last step: a worker killed half-way through sending a result (more than a pipe's
    buffer) leaves a partial message in the result pipe. The pool's manager thread then waits in
    ``recv`` for the rest, forever, because this process still holds a write end of that pipe;
    ``shutdown(wait=True)`` joins that thread, and the interrupted command hung with its workers
    defunct (1 CI run in 6, ``tests/reliability/test_kill.py``). With every worker gone, closing
    our write end turns the wait into end-of-file, which the pool handles as a broken pool.
    """
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for proc in procs:
        proc.terminate()
    for proc in procs:
        proc.join(10)
        if proc.is_alive():  # SIGTERM is SIG_DFL in workers; a worker stuck in C may need SIGKILL
            proc.kill()
            proc.join()
    writer = getattr(getattr(pool, "_result_queue", None), "_writer", None)
    if writer is not None:
        writer.close()


def _serial(fn: Callable[[T], R], items: Iterable[T], progress: Callable[[int], None] | None) -> Iterator[R]:
    for i, item in enumerate(items):
        try:
            result = fn(item)
        except Exception as exc:
            _note(exc, i, item, fn)
            raise
        yield result
        if progress:
            progress(1)


def parse_shard(text: str) -> tuple[int, int]:
    """``"I/N"`` -> ``(I, N)``: this process does part I (0-based) of N, as one task of a SLURM job
    array (``--shard $SLURM_ARRAY_TASK_ID/N``) does. Work that spreads over nodes goes through the
    scheduler's arrays; voe only says which part is whose (``voe score --shard``, ``voe gap bench --shard``).

    Raises:
        VoeError: not two whole numbers with 0 <= I < N.
    """
    i, _, n = text.partition("/")
    if not (i.isdigit() and n.isdigit() and 0 <= int(i) < int(n)):
        raise VoeError(f"--shard must be I/N with 0 <= I < N (e.g. $SLURM_ARRAY_TASK_ID/8), not {text!r}")
    return int(i), int(n)
