"""A generic registry with versioned ids, lazy ``module:attr`` entries and did-you-mean errors.

Why: concepts, models, lesions and gap effects are all looked up by name from the CLI and from
YAML. Following Gymnasium's registration, ids look like ``Name-v1``; asking for ``Name`` gives
the newest version. Entries may be registered lazily as ``"package.module:attr"`` strings so
that importing the registry never imports torch or pymunk.
"""

from __future__ import annotations

import difflib
import importlib
import re
from collections.abc import Callable, Iterator
from typing import Any, Generic, TypeVar

from voe.errors import UnknownNameError

T = TypeVar("T")
_ID = re.compile(r"^(?P<name>[A-Za-z0-9_.\-]+?)(?:-v(?P<version>\d+))?$")


def load_ref(ref: str) -> Any:
    """Import ``"package.module:attr"`` and return the attribute.

    Raises:
        UnknownNameError: the module or attribute does not exist.
    """
    if ":" not in ref:
        raise UnknownNameError(f"'{ref}' is not a 'package.module:attr' reference")
    mod_name, _, attr = ref.partition(":")
    try:
        module = importlib.import_module(mod_name)
    except ModuleNotFoundError as exc:
        raise UnknownNameError(f"cannot import module '{mod_name}' for '{ref}': {exc}") from exc
    obj: Any = module
    for part in attr.split("."):
        if not hasattr(obj, part):
            raise UnknownNameError(f"module '{mod_name}' has no attribute '{attr}' (from '{ref}')")
        obj = getattr(obj, part)
    return obj


def split_id(full_id: str) -> tuple[str, int | None]:
    """Split ``"Permanence-v2"`` into ``("Permanence", 2)``; unversioned ids give ``None``."""
    m = _ID.match(full_id)
    if not m:
        return full_id, None
    v = m.group("version")
    return m.group("name"), (int(v) if v is not None else None)


class Registry(Generic[T]):
    """Maps versioned ids to objects (or lazy ``module:attr`` refs to them).

    Args:
        kind: what is registered, for error messages ("concept", "model", ...).
    """

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self._entries: dict[str, T | str] = {}
        self._meta: dict[str, dict[str, Any]] = {}

    def register(self, full_id: str, entry: T | str | None = None, **meta: Any) -> Callable[[T], T] | T | str:
        """Register ``entry`` under ``full_id``; without ``entry``, act as a decorator."""

        def _add(obj: T | str) -> T | str:
            if full_id in self._entries:
                raise ValueError(f"{self.kind} '{full_id}' is already registered")
            self._entries[full_id] = obj
            self._meta[full_id] = dict(meta)
            return obj

        if entry is None:
            return _add  # type: ignore[return-value]
        return _add(entry)

    def ids(self) -> list[str]:
        """All registered ids, sorted."""
        return sorted(self._entries)

    def meta(self, full_id: str) -> dict[str, Any]:
        """Metadata given at registration time for the resolved id."""
        return self._meta[self.resolve(full_id)]

    def resolve(self, name: str) -> str:
        """Turn ``name`` (with or without ``-vN``, any case) into a registered id.

        Raises:
            UnknownNameError: no such id; the message suggests close matches.
        """
        if name in self._entries:
            return name
        base, version = split_id(name)
        candidates = []
        for full in self._entries:
            b, v = split_id(full)
            if b.lower() == base.lower() and (version is None or v == version):
                candidates.append((v or 0, full))
        if candidates:
            return max(candidates)[1]
        close = difflib.get_close_matches(name, self.ids(), n=3, cutoff=0.5)
        if not close:
            lower = {i.lower(): i for i in self.ids()}
            close = [lower[c] for c in difflib.get_close_matches(name.lower(), list(lower), n=3, cutoff=0.5)]
        hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
        raise UnknownNameError(f"unknown {self.kind} '{name}'{hint} (known: {', '.join(self.ids())})")

    def get(self, name: str) -> T:
        """Return the registered object, importing a lazy ``module:attr`` entry on first use."""
        full = self.resolve(name)
        entry = self._entries[full]
        if isinstance(entry, str):
            entry = load_ref(entry)
            self._entries[full] = entry
        return entry  # type: ignore[return-value]

    def __contains__(self, name: object) -> bool:
        try:
            self.resolve(str(name))
        except UnknownNameError:
            return False
        return True

    def __iter__(self) -> Iterator[str]:
        return iter(self.ids())

    def __len__(self) -> int:
        return len(self._entries)
