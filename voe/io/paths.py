"""Paths read from files stay inside their own directory; paths written are portable.

Why: a manifest, run, checkpoint config or controls file is data, and data must not steer voe
into reading anything else on the machine. A ``manifest.json`` entry ``../../../etc/hostname``
with that file's sha256 was once read, hashed and accepted. Every reader resolves such names
through ``inside``, which follows symlinks and refuses anything that lands outside the
directory. The other direction: outputs name their inputs by a path relative to the output
(``relative_ref``), so a report says nothing about the machine that made it.
"""

from __future__ import annotations

import os
from pathlib import Path

from voe.errors import VoeError


def inside(base: str | Path, name: object, source: str | Path, error: type[VoeError] = VoeError) -> Path:
    """``base / name``, refused unless it resolves (symlinks followed) inside ``base``.

    Args:
        base: the directory the name must stay in.
        name: the relative path read from a file (anything else is refused).
        source: the file the name was read from, for the message.
        error: the ``VoeError`` subclass to raise.

    Raises:
        error: ``name`` is not a non-empty relative path, or it leads outside ``base``.
    """
    if not isinstance(name, str | os.PathLike) or not str(name) or "\0" in str(name):
        raise error(f"{source}: {name!r} is not a file name")
    rel = Path(name)
    if rel.is_absolute():
        raise error(f"{source}: {str(name)!r} is an absolute path; only names inside {base} are allowed")
    root = Path(base).resolve()
    try:
        real = (root / rel).resolve()
    except (OSError, RuntimeError) as exc:  # symlink loops
        raise error(f"{source}: {str(name)!r} cannot be resolved: {exc}") from exc
    if not real.is_relative_to(root):
        raise error(f"{source}: {str(name)!r} leads outside {base} (to {real}); refusing to read it")
    return Path(base) / rel


def relative_ref(target: str | Path, out: str | Path) -> str | None:
    """``target`` as a POSIX path relative to the directory ``out``, or None if none exists.

    Why: recorded in outputs, it says how the output and its input sit side by side (it stays
    valid when both move together) and leaks no absolute path of the machine. Paths whose only
    common ancestor is the filesystem root (``/work/...`` against ``/home/...``) have no useful
    relative form: the caller names the input by its sha256 alone.
    """
    t, o = Path(target).resolve(), Path(out).resolve()
    common = Path(os.path.commonpath([t, o]))
    if common == Path(common.anchor):
        return None
    return Path(os.path.relpath(t, o)).as_posix()


def portable_ref(target: str | Path, out: str | Path) -> str:
    """``relative_ref`` or, where no relative path exists, the absolute path (machine records only:
    run.json and checkpoint configs, which must find their inputs again; never shown in reports)."""
    return relative_ref(target, out) or str(Path(target).resolve())


def resolve_ref(ref: str | Path, out: str | Path) -> Path:
    """Inverse of ``relative_ref``: a recorded relative path read back against ``out``.

    Absolute paths (older runs, or no relative path) are returned unchanged.
    """
    p = Path(ref)
    return p if p.is_absolute() else Path(out) / p


def show_path(path: str | Path, show: bool = False) -> str:
    """How an output prints a path: its name only, unless the user asked for paths."""
    return str(Path(path).resolve()) if show else Path(path).name
