"""Write-then-rename helpers, so nothing half-written is ever presented as complete.

Why: a crash (or Ctrl-C) in the middle of writing a probe set, checkpoint or report must leave
either the old output or nothing, never a directory that looks finished but isn't. The
temporary names start with a dot and say ``.tmp-``; a later writer of the same output removes
leftovers of killed writers. ``mkdtemp``/``mkstemp`` create owner-only (0700/0600) entries, so
the final output is given the mode it would have had if written directly (umask honoured).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from voe.errors import VoeError
from voe.io.lock import output_lock


def umask() -> int:
    """The process umask (read without changing it where the OS allows)."""
    with contextlib.suppress(OSError, ValueError):
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _clean_leftovers(out: Path) -> None:
    """Remove temporary siblings left by killed writers of ``out`` (we hold its lock)."""
    for p in out.parent.glob(f".{out.name}.tmp-*"):
        shutil.rmtree(p, ignore_errors=True) if p.is_dir() else p.unlink(missing_ok=True)


@contextlib.contextmanager
def atomic_dir(out: Path, overwrite: bool = False) -> Iterator[Path]:
    """Yield a temporary sibling directory; on success it is renamed to ``out``.

    Raises:
        VoeError: ``out`` exists and is not empty, and ``overwrite`` is false; ``out`` is a file.
        OutputLockedError: another live process is writing ``out``.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise VoeError(f"output {out} is a file, not a directory")
    if out.exists() and any(out.iterdir()) and not overwrite:
        raise VoeError(f"output directory {out} already exists and is not empty (pass --overwrite)")
    out.parent.mkdir(parents=True, exist_ok=True)
    with output_lock(out):
        _clean_leftovers(out)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.tmp-", dir=out.parent))
        try:
            yield tmp
            tmp.chmod(0o777 & ~umask())
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        if out.exists():
            old = out.with_name(f".{out.name}.tmp-old-{os.getpid()}")
            out.rename(old)
            tmp.rename(out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(out)


def atomic_write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and an atomic rename."""
    path = Path(path)
    if path.is_dir():
        raise VoeError(f"output {path} is a directory, not a file")
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.tmp-", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o666 & ~umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def atomic_write_text(path: Path, text: str) -> None:
    atomic_write_bytes(path, text.encode("utf-8"))
