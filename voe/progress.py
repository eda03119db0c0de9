"""The one progress bar of voe: a tqdm bar on stderr behind a plain ``tick(n)`` callback.

Why a callback: the layers that do the work (generation, scoring, controls) take an optional
``progress: Callable[[int], None]`` and never import tqdm, so they stay usable from scripts and
tests without a terminal. Whoever starts the work (the CLI, the demo, the validity suite) opens
the bar here and passes its ``tick`` down. stdout stays free for results.
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Callable, Iterator

Tick = Callable[[int], None]


def no_progress(_: int = 1) -> None:
    """A ``tick`` that shows nothing (the default of every worker-side function)."""


@contextlib.contextmanager
def progress(total: int | None, desc: str, unit: str = "it", enabled: bool = True) -> Iterator[Tick]:
    """A progress bar on stderr; yields its ``tick(n)`` function (advance by ``n``).

    Args:
        total: expected number of ticks (None for an open-ended bar).
        desc: what is being counted, e.g. ``"training clips"``.
        unit: the unit of one tick, e.g. ``"clip"``.
        enabled: False yields ``no_progress`` (e.g. for quiet runs and worker processes).
    """
    if not enabled:
        yield no_progress
        return
    from tqdm import tqdm

    with tqdm(total=total, desc=desc, unit=unit, dynamic_ncols=True, leave=True, file=sys.stderr) as bar:
        yield bar.update
