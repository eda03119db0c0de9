"""Benchmark the built-in models on this machine: training and scoring throughput, validation NLL.

Prints one line per model: training throughput (frames/s; references: calibration), scoring
throughput (frames/s of ``frame_nll``), and validation NLL (nats per scored frame) of each learned
model next to its matching reference (state models vs constant velocity, pixel model vs frame copy)
on the same held-out clips.

Usage::

    voe world generate --n 1200 --seed 0 --out /tmp/world --jobs 2
    python bench/models_bench.py --data /tmp/world [--steps N]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from voe.models.loading import load_model
from voe.models.train import TrainConfig, fit, split_batches, val_nll

PAIRS = {"mlp-v2": "constvel-v1", "interaction-v3": "constvel-v1", "pixel-v1": "framecopy-v1"}
REFERENCES = ("constvel-v1", "framecopy-v1", "oracle-v1")


def scoring_speed(model, batch) -> float:
    start = time.perf_counter()
    model.frame_nll(batch)
    return batch.shape[0] * batch.shape[1] / (time.perf_counter() - start)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, required=True, help="training set (voe world generate)")
    ap.add_argument("--steps", type=int, default=None, help="training steps per learned model (default: its preset)")
    ap.add_argument("--val-frac", type=float, default=0.1)
    ap.add_argument("--models", nargs="*", default=[*REFERENCES, *PAIRS])
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()

    import torch

    torch.set_num_threads(1)
    train, val, _ = split_batches(args.data, args.val_frac, args.seed)
    sub = val.take(slice(0, min(len(val), 32)))
    print(f"data {args.data}: {len(train)} train / {len(val)} val clips x {train.shape[1]} frames; "
          f"torch threads 1; {args.steps or 'preset'} steps per learned model")
    ref_nll: dict[str, float] = {}
    rows = []
    for mid in args.models:
        model = load_model(mid, {"seed": args.seed} if mid in PAIRS else None)
        start = time.perf_counter()
        if mid in PAIRS:
            summary = fit(model, train, val, TrainConfig(steps=args.steps, seed=args.seed, eval_every=250))
            train_fps, nll = summary["train_frames_per_s"], summary["val_nll"]
            extra = f"{summary['steps']} steps in {summary['seconds']:.0f} s"
        else:
            model.calibrate(train)
            frames = train.shape[0] * (train.shape[1] - 1)
            train_fps, nll = frames / (time.perf_counter() - start), val_nll(model, val)
            ref_nll[mid] = nll
            extra = "calibration (ML noise)"
        rows.append((mid, train_fps, scoring_speed(model, sub), nll, extra))
    print(f"{'model':<16} {'train fr/s':>11} {'score fr/s':>11} {'val NLL':>10} {'reference':>22}  notes")
    for mid, tfps, sfps, nll, extra in rows:
        ref = PAIRS.get(mid)
        refs = f"{ref.split('-v')[0]} {ref_nll[ref]:.2f}" if ref in ref_nll else ""
        better = "" if not refs else ("  better" if nll < ref_nll[ref] else "  WORSE")
        print(f"{mid:<16} {tfps:>11.0f} {sfps:>11.0f} {nll:>10.2f} {refs:>22}{better}  {extra}", flush=True)


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
