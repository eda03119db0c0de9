"""Small helpers shared by CLI groups: option parsing (and the progress bar, re-exported)."""

from __future__ import annotations

from voe.errors import VoeError
from voe.progress import progress

__all__ = ["parse_kv", "progress"]


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
