"""Sensitivity check: random ``interaction-v2`` networks whose state-head gates are random too.

Why: the random-network control (``voe.controls.random_nets``) keeps the head's gates at their
initial value, zero, so a random v2 network forgets hidden objects and ties the hidden splices.
The gates multiply a built-in Euler step; with them open, a random network carries hidden objects
at constant velocity. This script measures what such networks score, to show how much of the
trained model's credit the gated step alone could give.

Usage: python bench/random_gates.py PROBES [--seeds 10]   (use a development probe set)
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import pandas as pd
import torch

from voe.controls.random_nets import random_network
from voe.report.build import build_report
from voe.scoring.score import score_probe_set


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("probes", type=Path)
    ap.add_argument("--seeds", type=int, default=10)
    a = ap.parse_args()
    out = Path(tempfile.mkdtemp(prefix="voe-random-gates-"))
    runs = []
    for s in range(a.seeds):
        m = random_network("interaction", s)
        g = torch.Generator().manual_seed(1000 + s)
        with torch.no_grad():
            head = m.net.head
            head.theta.copy_(torch.rand(head.theta.shape, generator=g) / head.GAIN)  # gates U(0, 1)
        m.name = f"random-gates-s{s}"
        score_probe_set(m, a.probes, out / m.name, model_ref="interaction", batch_size=32)
        runs.append(out / m.name)
    build_report(runs, out / "report", title="random interaction-v2 nets, random gates", overwrite=True)
    s = pd.read_csv(out / "report" / "summary.csv")
    print(s.pivot(index="model", columns="concept", values="accuracy").round(2).to_string())
    print("learned:", s[s.verdict == "learned"].groupby("concept").size().to_dict())


if __name__ == "__main__":
    main()
