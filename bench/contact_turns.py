"""Does an object-centric checkpoint foresee a contact in view: at the frames where a visible
object's velocity turns round (a bounce off a wall, the floor or another object), how much of the
jump does its one-step prediction make?

Why (session 16): solidity and collision turn on a hidden object bouncing off a wall or hitting a
target behind a screen at the right frame, so a rollout can only get them if the network's step
turns an object round at a contact. This is the cheapest falsifier of that, with no training and
no hidden rollout: the frames are *visible* (the state at t is the observation), so a model that has
learned contacts predicts at least part of the turn. Per velocity component it prints the number
of turn-round steps (sign change, |v| above 0.5 on both sides), the share where the predicted
velocity already has the new sign, and the median and 90th percentile of the share of the jump
predicted, ``(predicted - before) / (after - before)`` (0: the model expects the object to go on;
1: it foresees the contact).

    python bench/contact_turns.py CKPT DATA [--clips 200] [--concept solidity ...]

``DATA`` is a probe set (its *possible* clips of the given concepts, both conditions) or a training
world (its first clips). Development data only.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch


def main() -> None:
    from voe.io.probeset import load_probe_set
    from voe.models.checkpoint import read_checkpoint
    from voe.models.interaction import rollout_nll
    from voe.models.loading import load_model

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ckpt", type=Path)
    ap.add_argument("data", type=Path)
    ap.add_argument("--clips", type=int, default=200)
    ap.add_argument("--concept", action="append", default=[])
    a = ap.parse_args()
    m = load_model(read_checkpoint(a.ckpt)["model"], None, a.ckpt)
    ps = load_probe_set(a.data)
    idx = ps.index
    keep = idx.role == "possible" if "possible" in set(idx.role) else idx.role != "impossible"
    if a.concept:
        keep &= idx.concept_name.isin(a.concept)
    ids = list(idx.clip_id[keep])[: a.clips]
    if not ids:
        raise SystemExit(f"contact_turns: no possible clips in {a.data}")
    hit: dict[str, list[bool]] = {"vx": [], "vy": []}
    share: dict[str, list[float]] = {"vx": [], "vy": []}
    names = list(ps.feature_names)
    m.net.eval()
    for i in range(0, len(ids), 50):
        b = ps.batch(ids[i:i + 50])
        steps: list[tuple[torch.Tensor, ...]] = []
        with torch.no_grad():
            rollout_nll(m.net, m.prepare(b), steps)
        mean = torch.stack([s[0] for s in steps], 1).double().numpy()  # (B, T-1, K, 9): frame t+1
        st, pr = b.states, b.present
        vis = pr[:, :-1] & pr[:, 1:]
        for f in ("vx", "vy"):
            j = names.index(f)  # the state's column; the prediction's is 3 (vx) or 4 (vy) as well
            v0, v1 = st[:, :-1, :, j], st[:, 1:, :, j]
            turn = vis & (np.sign(v0) != np.sign(v1)) & (np.abs(v0) > 0.5) & (np.abs(v1) > 0.5)
            pred = mean[..., 3 if f == "vx" else 4][turn]
            hit[f] += list(np.sign(pred) == np.sign(v1[turn]))
            share[f] += list((pred - v0[turn]) / (v1[turn] - v0[turn]))
    print(f"{m.name} on {len(ids)} possible clips of {a.data}")
    for f in ("vx", "vy"):
        if not hit[f]:
            print(f"  {f}: no turn-round steps in view")
            continue
        print(f"  {f}: turn-round steps in view n={len(hit[f])}, predicted turned {np.mean(hit[f]):.2f}, "
              f"share of the jump predicted: median {np.median(share[f]):+.3f}, 90th pct {np.percentile(share[f], 90):+.3f}")


if __name__ == "__main__":
    main()
