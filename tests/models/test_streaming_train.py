"""Training reads a sharded world a group of shards at a time, never the whole world."""

from __future__ import annotations

import numpy as np
import pytest

from voe.io.probeset import load_probe_set
from voe.models.clips import Clips, GroupSampler
from voe.models.train import TrainConfig, split_clips, train, val_nll
from voe.sim.scene import SimConfig
from voe.world.generate import generate_world


@pytest.fixture(scope="module")
def sharded_world(tmp_path_factory):
    out = tmp_path_factory.mktemp("sharded") / "w"
    mp = pytest.MonkeyPatch()
    mp.setattr("voe.io.shards.MAX_SHARD_CLIPS", 4)
    try:
        generate_world(out, 20, 3, SimConfig(n_frames=12, size=16))
    finally:
        mp.undo()
    return out


def test_groups_are_whole_shards_within_capacity(sharded_world):
    ps = load_probe_set(sharded_world)
    assert [n for _, n in ps.shards] == [4] * 5
    ids = [c for c in ps.index.clip_id if c not in ("train-000001", "train-000009")]
    groups = Clips(ps, ids).groups(7)
    assert [len(g) for g in groups] == [7, 7, 4]  # (3+4), (3+4), 4: shards are not split
    assert sum(groups, []) == ids
    assert Clips(ps, ids).groups(2)[0] == ids[:2]  # a shard larger than capacity is cut
    order = [tuple(GroupSampler(groups, 0).next()) for _ in range(1)]
    assert order[0] in {tuple(g) for g in groups}


def test_training_visits_groups_and_holds_one_at_a_time(sharded_world, tmp_path, monkeypatch):
    loaded = []
    real = Clips.load

    def spy(self, ids=None):
        batch = real(self, ids)
        loaded.append(len(batch))
        return batch

    monkeypatch.setattr(Clips, "load", spy)
    cfg = TrainConfig(steps=24, val_frac=0.2, eval_every=12, buffer_clips=8, group_draws=1)
    meta = train("mlp", sharded_world, tmp_path / "ck", cfg)
    assert meta["train_groups"] >= 2 and meta["n_train"] == 16
    assert max(loaded) <= 8 and len(loaded) >= 3  # several group loads, each within the buffer
    assert np.isfinite(meta["val_nll"])
    _, val, _ = split_clips(sharded_world, 0.2, 0)
    from voe.models.loading import load_model

    assert val_nll(load_model("mlp", checkpoint=tmp_path / "ck"), val, chunk=3) == pytest.approx(meta["val_nll"])
