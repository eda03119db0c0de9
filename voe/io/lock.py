"""One writer per output: a lock file with the writer's pid next to the output.

Why: two processes writing the same output directory would each rename their result over the
other's, or one would read the other's half-written scratch files. The second writer refuses and
names the first. A lock left by a process that died (SIGKILL, power loss) names a pid that no
longer runs; it is taken over, so a crash never needs manual cleanup.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

from voe.errors import VoeError

_HELD: dict[str, int] = {}  # lock path -> nesting depth; inherited by forked workers


class OutputLockedError(VoeError):
    """Another live process is writing the same output."""


def lock_path(out: str | Path) -> Path:
    out = Path(out).absolute()
    return out.parent / f".{out.name}.lock"


def _holder(lock: Path) -> int | None:
    try:
        return int(lock.read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's live process
        return True
    return True


def _acquire(lock: Path, out: Path) -> None:
    lock.parent.mkdir(parents=True, exist_ok=True)
    me = f"{os.getpid()}\n"
    for _ in range(3):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666)
        except FileExistsError:
            pid = _holder(lock)
            if pid is not None and pid != os.getpid() and _alive(pid):
                raise OutputLockedError(f"{out} is being written by process {pid} (lock file {lock}); "
                                        "wait for it to finish, or write elsewhere") from None
            tmp = lock.with_name(f"{lock.name}.{os.getpid()}")
            tmp.write_text(me)
            os.replace(tmp, lock)  # stale (dead pid) or unreadable: take it over
        else:
            with os.fdopen(fd, "w") as fh:
                fh.write(me)
        if _holder(lock) == os.getpid():  # a racing taker may have replaced it: check who won
            return
    raise OutputLockedError(f"{out}: could not take the lock file {lock}")


@contextlib.contextmanager
def output_lock(out: str | Path) -> Iterator[Path]:
    """Hold the lock of output ``out`` (re-entrant within a process and its forked workers)."""
    lock = lock_path(out)
    key = str(lock)
    if _HELD.get(key):
        _HELD[key] += 1
        try:
            yield lock
        finally:
            _HELD[key] -= 1
        return
    _acquire(lock, Path(out))
    _HELD[key] = 1
    try:
        yield lock
    finally:
        _HELD[key] -= 1
        if not _HELD[key]:
            del _HELD[key]
            if _holder(lock) == os.getpid():
                with contextlib.suppress(FileNotFoundError):
                    lock.unlink()
