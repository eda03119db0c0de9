"""The null effect: no parameters, nothing changes. The nominal scene is ``none``."""

from __future__ import annotations

from voe.gap.effects.base import Effect


class NoEffect(Effect):
    name = "none"
    summary = "nothing is missing"
