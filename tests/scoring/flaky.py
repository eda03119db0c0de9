"""A model that fails once, on one chosen clip, like a GPU fault or a bug hit by one input."""

from __future__ import annotations

from pathlib import Path

from voe.testing import RandomModel


class FlakyModel(RandomModel):
    """``RandomModel`` that raises on the batch holding clip key ``fail_key`` until ``marker`` exists
    (it creates the marker as it fails, so a rerun gets through). ``calls`` counts clips scored."""

    def __init__(self, fail_key: str, marker: str, count: str = "") -> None:
        super().__init__(0)
        self.name, self.fail_key, self.marker, self.count = "flaky", fail_key, Path(marker), count

    def frame_nll(self, batch):
        if self.fail_key in batch.clip_ids and not self.marker.exists():
            self.marker.touch()
            raise RuntimeError("simulated device fault\nwith a second line")
        if self.count:
            with open(self.count, "a") as fh:
                fh.write(f"{len(batch)}\n")
        return super().frame_nll(batch)


class SlowModel(RandomModel):
    """``RandomModel`` that takes ``delay`` seconds per batch, to be killed partway."""

    def __init__(self, delay: float = 0.2) -> None:
        super().__init__(0)
        self.delay = float(delay)

    def frame_nll(self, batch):
        import time

        time.sleep(self.delay)
        return super().frame_nll(batch)
