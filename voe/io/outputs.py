"""Check an output path before any work starts, and hold it for the whole command.

Why: ``voe probes generate --out FILE`` once ended in a ``NotADirectoryError`` traceback, and an
existing non-empty directory was refused only after the whole suite had been generated. Every
command now calls ``claim_output`` first: the path's kind (directory or file), whether it exists
(``--overwrite``), whether it can be written, and whether another process is writing it.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

from voe.errors import VoeError
from voe.io.lock import output_lock


def _nearest_existing(path: Path) -> Path:
    p = path.absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def check_output(out: str | Path, kind: str = "dir", overwrite: bool = False,
                 suffixes: tuple[str, ...] = (), option: str = "--out", replaces: tuple[str, ...] = ()) -> Path:
    """Refuse an output path that cannot be written as asked; returns it as a ``Path``.

    Args:
        out: the output path.
        kind: ``"dir"`` (a directory, new or empty unless ``overwrite``) or ``"file"``.
        overwrite: an existing output may be replaced.
        suffixes: allowed file suffixes (``kind="file"`` only), e.g. ``(".png", ".gif")``.
        option: the command-line option named in messages.
        replaces: marker files of this command's own earlier output (e.g. ``("report.md",)``):
            a directory holding one is replaced without ``overwrite`` (commands with a default
            output path, rerun in place); any other non-empty directory is refused.

    Raises:
        VoeError: wrong kind, exists without ``overwrite``, wrong suffix, or not writable.
    """
    out = Path(out)
    if kind == "dir":
        if out.exists() and not out.is_dir():
            raise VoeError(f"{option} {out} is a file; give a directory (new or empty)")
        if (out.is_dir() and any(out.iterdir()) and not overwrite
                and not any((out / m).is_file() for m in replaces)):
            raise VoeError(f"{option} {out} already exists and is not empty (pass --overwrite to replace it)")
    else:
        if out.is_dir():
            raise VoeError(f"{option} {out} is a directory; give a file name")
        if suffixes and out.suffix.lower() not in suffixes:
            raise VoeError(f"{option} {out}: use a {', '.join(suffixes)} file")
        if out.exists() and not overwrite:
            raise VoeError(f"{option} {out} already exists (pass --overwrite to replace it)")
    base = _nearest_existing(out.parent)
    if not base.is_dir():
        raise VoeError(f"{option} {out}: {base} is a file, so nothing can be created under it")
    if not os.access(base, os.W_OK | os.X_OK):
        raise VoeError(f"{option} {out}: {base} is not writable")
    return out


@contextlib.contextmanager
def claim_output(out: str | Path, kind: str = "dir", overwrite: bool = False,
                 suffixes: tuple[str, ...] = (), option: str = "--out",
                 replaces: tuple[str, ...] = ()) -> Iterator[Path]:
    """``check_output``, then hold the output's lock until the command ends."""
    out = check_output(out, kind, overwrite, suffixes, option, replaces)
    with output_lock(out):
        yield out


def scratch_dir(name: str) -> Path:
    """A per-user scratch directory for reusable intermediate data: ``$XDG_CACHE_HOME/voe/NAME-CODE``.

    Why: scratch data once landed in ``voe-work/`` under whatever directory a command was started
    from. ``~/.cache/voe/...`` is used when ``XDG_CACHE_HOME`` is unset. ``CODE`` is
    :func:`code_fingerprint`: commands reuse what a scratch directory holds (probes, worlds,
    checkpoints, runs) by its presence, so after an upgrade a rerun once reported runs of the old
    probe designs and models as new; a directory per code version makes reuse safe.
    """
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "voe" / f"{name}-{code_fingerprint()}"


def code_fingerprint(root: Path | None = None) -> str:
    """12 hex digits of sha256 over the package's Python sources and the concept specs.

    Args:
        root: the source checkout (default: the one this module was imported from); its
            ``voe/**/*.py`` and ``probes/*/spec.yaml`` are hashed, path and bytes, in sorted order.
    """
    import hashlib

    root = Path(__file__).resolve().parents[2] if root is None else Path(root)
    files = sorted([*(root / "voe").rglob("*.py"), *(root / "probes").glob("*/spec.yaml")])
    h = hashlib.sha256()
    for f in files:
        h.update(f.relative_to(root).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()[:12]
