"""Small helpers shared by CLI groups: option parsing (and the progress bar, re-exported)."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

from voe.errors import VoeError
from voe.progress import progress

__all__ = ["claims_output", "parse_kv", "progress"]


def parse_kv(items: list[str] | None) -> dict[str, object]:
    """Parse repeated ``key=value`` options; values become int, float, bool or str."""
    out: dict[str, object] = {}
    for item in items or []:
        if "=" not in item:
            raise VoeError(f"expected key=value, got '{item}'")
        key, _, raw = item.partition("=")
        value: object = raw
        low = raw.lower()
        if low in ("true", "false"):
            value = low == "true"
        else:
            for cast in (int, float):
                try:
                    value = cast(raw)
                    break
                except ValueError:
                    continue
        out[key.strip()] = value
    return out


def claims_output(kind: str = "dir", suffixes: tuple[str, ...] = (), option: str = "out",
                  replaces: tuple[str, ...] = ()) -> Callable:
    """Decorate a command: check its output path and hold its lock before the body runs.

    Why a decorator: every command needs the same preconditions (file vs directory, exists and
    ``--overwrite``, writable, no other writer) *before* computing, and one line per command is
    what keeps them from being forgotten. The command's ``--overwrite`` (if any) is honoured.
    """
    def deco(fn: Callable) -> Callable:
        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            from voe.io.outputs import claim_output

            out = kwargs.get(option)
            if out is None:
                return fn(*args, **kwargs)
            with claim_output(out, kind, bool(kwargs.get("overwrite", False)), suffixes, f"--{option}",
                              replaces):
                return fn(*args, **kwargs)
        return wrapper
    return deco
