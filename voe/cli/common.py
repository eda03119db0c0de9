"""Small helpers shared by CLI groups: progress bars and option parsing."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from voe.errors import VoeError


@contextlib.contextmanager
def progress(total: int, desc: str, unit: str = "it") -> Iterator:
    """A tqdm progress bar on stderr; yields its ``update`` function."""
    from tqdm import tqdm

    with tqdm(total=total, desc=desc, unit=unit, dynamic_ncols=True, leave=True) as bar:
        yield bar.update


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
