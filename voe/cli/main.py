"""Entry point of the ``voe`` command: assembles the command groups and maps errors to exit codes.

Why: every library error is a ``VoeError``; here, and only here, it becomes a one-line message on
stderr and a non-zero exit (1 for user errors, 2 for broken contracts). Each command group lives
in its own file and keeps heavy imports (torch, matplotlib, pymunk) inside its functions so that
``voe --help`` starts instantly.
"""

from __future__ import annotations

import importlib
import signal
import sys

import typer

from voe.errors import VoeError

app = typer.Typer(
    name="voe",
    help="Violation-of-expectation probes, scoring and reports for learned physics simulators.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

# (module under voe.cli, group name or None to add its commands at top level)
_GROUPS: list[tuple[str, str | None]] = [
    ("probes", "probes"),
    ("world", "world"),
    ("model", "model"),
    ("train", None),
    ("score", None),
    ("report", None),
    ("demo", None),
    ("validate", None),
    ("gap", "gap"),
]

for _mod, _name in _GROUPS:
    try:
        _sub = importlib.import_module(f"voe.cli.{_mod}")
    except ModuleNotFoundError as _exc:  # a group not written yet
        if _exc.name != f"voe.cli.{_mod}":
            raise
        continue
    if _name is None:
        _sub.register(app)
    else:
        app.add_typer(_sub.app, name=_name)


def main() -> None:
    """Run the CLI; turn ``VoeError`` into ``voe: error: ...`` and its exit code.

    Usage errors (bad options) are handled by typer itself and exit with 2. SIGTERM is turned
    into an exception like Ctrl-C, so both unwind the same way: temporary outputs are removed,
    locks released, and nothing half-written is left under a final name. Either ends in one
    ``voe: interrupted`` line and exit code 130.
    """
    signal.signal(signal.SIGTERM, _interrupt)
    if hasattr(signal, "setitimer"):  # not on Windows
        signal.signal(signal.SIGALRM, _again)
        sys.unraisablehook = _unraisable
    if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:  # a background job keeps ignoring it
        signal.signal(signal.SIGINT, _interrupt)
    try:
        app()
    except VoeError as exc:
        typer.echo(f"voe: error: {exc}", err=True)
        sys.exit(exc.exit_code)
    except (KeyboardInterrupt, SystemExit) as exc:  # click turns Ctrl-C into "Aborted!" and exit 1
        if not _INTERRUPTED:
            raise
        if isinstance(exc, SystemExit) and exc.code in (0, None):
            _swallowed()
        typer.echo(f"voe: interrupted by {_INTERRUPTED[0]}; nothing incomplete was kept under a final "
                   "name (rerun to resume or start again)", err=True)
        sys.exit(130)
    if _INTERRUPTED:
        _swallowed()


def _swallowed() -> None:
    """The signal's exception was raised where Python ignores exceptions (an at-fork or finalizer
    callback: "Exception ignored in ... _releaseLock" right after a worker was forked), so the
    command ran on to its end. Its outputs are complete, but the caller asked it to stop: say so
    and exit non-zero, as a stopped command does."""
    typer.echo(f"voe: {_INTERRUPTED[0]} arrived where it could not stop the command, which ran to its end; "
               "its outputs are complete", err=True)
    sys.exit(130)


_INTERRUPTED: list[str] = []


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM, raised where the main thread is so that cleanup runs."""


def _unraisable(hook_args: object) -> None:
    """``sys.unraisablehook``: an ``Interrupted`` that Python had to ignore is raised again.

    Why: a signal handler runs at whatever bytecode the main thread is at, and some places
    swallow what it raises: at-fork callbacks (logging's ``_releaseLock``), finalizers, cffi
    callbacks (pymunk's ``freebody``). The command then printed a traceback and ran on to its end.
    Here a 10 ms timer is armed instead, whose handler (``_again``) raises it from ordinary code;
    should that land in such a place too, this hook arms it again.
    """
    if isinstance(getattr(hook_args, "exc_value", None), Interrupted):
        signal.setitimer(signal.ITIMER_REAL, 0.01)
        return
    sys.__unraisablehook__(hook_args)


def _again(signum: int, frame: object) -> None:
    raise Interrupted()


def _interrupt(signum: int, frame: object) -> None:
    signal.signal(signum, signal.SIG_DFL)  # a second signal ends the process at once
    _INTERRUPTED.append(signal.Signals(signum).name)
    raise Interrupted()


if __name__ == "__main__":  # pragma: no cover
    main()
