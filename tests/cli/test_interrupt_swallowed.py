"""A signal whose exception Python swallowed still ends the command non-zero.

Why: SIGTERM that lands in an at-fork callback (logging's ``_releaseLock`` right after a worker is
forked) raises where Python prints "Exception ignored" and goes on; the command then ran to its
end and exited 0 although it was told to stop (seen once in CI, tests/reliability/test_kill.py).
"""

from __future__ import annotations

import signal

import pytest

import voe.cli.main as cli


def _main() -> int | None:
    """``cli.main()`` with the signal handlers and unraisable hook it installs put back after;
    returns its exit code (``None`` if it returned)."""
    import sys

    old = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGINT, signal.SIGALRM)}
    hook = sys.unraisablehook
    try:
        cli.main()
    except SystemExit as exc:
        return exc.code
    finally:
        sys.unraisablehook = hook
        for s, h in old.items():
            signal.signal(s, h)
    return None


@pytest.mark.parametrize("ending", ["return", "exit0"])
def test_swallowed_signal_exits_130(monkeypatch, capsys, ending):
    def app():
        cli._INTERRUPTED.append("SIGTERM")  # what the handler records before its raise was lost
        if ending == "exit0":
            raise SystemExit(0)

    monkeypatch.setattr(cli, "app", app)
    monkeypatch.setattr(cli, "_INTERRUPTED", [])
    assert _main() == 130
    assert "SIGTERM arrived where it could not stop the command" in capsys.readouterr().err


def test_a_normal_run_is_untouched(monkeypatch):
    monkeypatch.setattr(cli, "app", lambda: None)
    monkeypatch.setattr(cli, "_INTERRUPTED", [])
    assert _main() is None


def test_an_interrupt_python_had_to_ignore_is_raised_again_from_ordinary_code(monkeypatch, capsys):
    """A finalizer (here ``__del__``, in CI a cffi callback of pymunk) swallows the handler's raise;
    the command must still stop, not print a traceback and run on."""
    import gc
    import time

    class Finalized:
        def __del__(self):
            raise cli.Interrupted()  # what _interrupt raises, landing in a finalizer

    def app():
        Finalized()  # freed at once: its raise is "ignored"
        gc.collect()
        for _ in range(500):  # the command would run on to its end
            time.sleep(0.002)
        raise AssertionError("ran to its end")

    monkeypatch.setattr(cli, "app", app)
    monkeypatch.setattr(cli, "_INTERRUPTED", ["SIGTERM"])
    assert _main() == 130
    err = capsys.readouterr().err
    assert "interrupted by SIGTERM" in err and "Traceback" not in err
