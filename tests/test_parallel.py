"""``voe.parallel.parallel_map`` and ``voe.progress``: order, laziness, errors, layering."""

from __future__ import annotations

import ast
import os
import threading
import time
from pathlib import Path

import pytest

from voe.errors import ConceptError, VoeError
from voe.parallel import parallel_map
from voe.progress import no_progress, progress

VOE = Path(__file__).resolve().parents[1] / "voe"


def _slow_square(x: int) -> int:
    time.sleep(0.02 * (x % 3 == 0))  # every third item finishes last: completion order != input order
    return x * x


def _tens(x: int) -> int:
    return x * 10


def _nested(x: int) -> int:
    return sum(parallel_map(_tens, range(x), 2))


def _die(x: int) -> int:
    os._exit(3)  # a worker killed from outside (out of memory) looks like this


def _fail_on_5(x: int) -> int:
    if x == 5:
        raise ConceptError(f"item {x} is bad")
    return x


@pytest.mark.parametrize("jobs", [1, 2, 3])
def test_results_in_input_order_with_progress(jobs):
    ticks = []
    out = list(parallel_map(_slow_square, range(12), jobs, progress=ticks.append))
    assert out == [x * x for x in range(12)]
    assert ticks == [1] * 12


def test_items_are_consumed_lazily():
    pulled = []

    def items():
        for i in range(100):
            pulled.append(i)
            yield i

    it = parallel_map(_slow_square, items(), jobs=2, ahead=2)
    assert next(it) == 0
    assert len(pulled) <= 2 * 2 + 1  # the window, not the whole input
    it.close()
    serial = parallel_map(_slow_square, items(), jobs=1)
    pulled.clear()
    assert next(serial) == 0 and pulled == [0]


@pytest.mark.parametrize("jobs", [1, 2])
def test_worker_error_keeps_its_type_and_names_the_item(jobs):
    with pytest.raises(ConceptError, match="item 5 is bad") as info:
        list(parallel_map(_fail_on_5, range(8), jobs))
    notes = "".join(getattr(info.value, "__notes__", []))
    assert "_fail_on_5 failed on item 5" in notes
    if jobs > 1:  # the worker's traceback travels as the cause
        assert "_fail_on_5" in str(info.value.__cause__)


def test_forked_workers_inherit_closures_over_unpicklable_state():
    lock = threading.Lock()  # cannot be pickled

    def with_lock(x: int) -> int:
        with lock:
            return x + 1

    assert list(parallel_map(with_lock, [1, 2, 3], jobs=2, start_method="fork")) == [2, 3, 4]


def test_nested_pools_and_dead_workers():
    assert list(parallel_map(_nested, [3, 4], 2)) == [30, 60]  # e.g. a control generating a world
    with pytest.raises(VoeError, match="worker process died .* item 0"):
        list(parallel_map(_die, [1, 2], 2))


def test_progress_helper(capsys):
    with progress(3, "things", "thing") as tick:
        tick(2)
        tick(1)
    err = capsys.readouterr().err
    assert "things" in err and "3/3" in err
    with progress(3, "quiet", enabled=False) as tick:
        assert tick is no_progress
    assert "quiet" not in capsys.readouterr().err


def test_nothing_outside_cli_imports_cli():
    offenders = []
    for path in VOE.rglob("*.py"):
        if path.relative_to(VOE).parts[0] in ("cli", "__main__.py"):  # the CLI and its entry point
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = []
            if isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            if any(n == "voe.cli" or n.startswith("voe.cli.") for n in names):
                offenders.append(f"{path.relative_to(VOE.parent)}:{node.lineno}")
    assert not offenders, f"voe.cli imported outside voe/cli: {offenders}"


def test_no_private_pool_loops_left():
    """One ``parallel_map``: no other module builds its own process pool."""
    pools = [str(p.relative_to(VOE.parent)) for p in VOE.rglob("*.py")
             if p.name != "parallel.py" and any(s in p.read_text() for s in ("ProcessPoolExecutor", ".Pool("))]
    assert not pools, pools


def _handlers(_: int) -> tuple[bool, bool]:
    import signal

    return signal.getsignal(signal.SIGTERM) == signal.SIG_DFL, signal.getsignal(signal.SIGINT) == signal.SIG_IGN


def test_workers_end_quietly_on_sigterm_instead_of_running_the_parents_handler():
    """The parent stops its workers with SIGTERM; a forked worker must not run the CLI's handler
    (it raised ``Interrupted`` in the worker and printed a traceback under the one-line message)."""
    import signal

    def loud(signum, frame):  # what voe.cli.main installs
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGTERM, loud)
    try:
        assert list(parallel_map(_handlers, [1, 2], 2, start_method="fork")) == [(True, True)] * 2
    finally:
        signal.signal(signal.SIGTERM, old)


def test_a_signal_sent_from_another_thread_while_forking_waits_for_the_fork_to_end():
    """The kernel may hand the signal to any thread that does not block it; the handler must
    still not run inside the held section (it ran inside at-fork callbacks and was lost)."""
    import os
    import signal
    import threading
    import time

    from voe.parallel import signals_held

    calls: list[str] = []

    def handler(signum, frame):
        calls.append("handled")

    old = signal.signal(signal.SIGTERM, handler)
    try:
        with signals_held():
            t = threading.Thread(target=lambda: os.kill(os.getpid(), signal.SIGTERM))
            t.start()
            t.join()
            for _ in range(200):  # bytecode boundaries where a Python handler would run
                time.sleep(0.001)
            calls.append("section over")
        assert calls == ["section over", "handled"]
        assert signal.getsignal(signal.SIGTERM) is handler
    finally:
        signal.signal(signal.SIGTERM, old)


_INTERRUPT_MID_RESULT = """
import os, signal, threading
from voe.parallel import parallel_map

def big(i):
    return b"x" * (8 << 20)  # many pipe buffers: a worker is killed in the middle of sending one

def interrupted(signum, frame):
    raise KeyboardInterrupt  # what voe.cli.main's SIGTERM handler raises

signal.signal(signal.SIGTERM, interrupted)
try:
    for n, _ in enumerate(parallel_map(big, range(400), 2)):
        if n == 0:  # the workers are busy sending results from now on
            threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGTERM)).start()
except KeyboardInterrupt:
    print("stopped")
"""


@pytest.mark.parametrize("attempt", range(3))
def test_an_interrupt_while_workers_send_large_results_ends_instead_of_hanging(attempt):
    """Workers killed mid-send left a partial message that the pool's manager thread waited on
    forever (the command hung at shutdown with defunct workers). Fails (times out) on the old code."""
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", _INTERRUPT_MID_RESULT], capture_output=True, text=True,
                          timeout=60, cwd=VOE.parent)
    assert proc.returncode == 0 and proc.stdout.strip() == "stopped", proc.stderr
