"""Random networks of one learned architecture on a probe set: are they at chance everywhere?

Why: the random-network control (``voe.controls.random_nets``) is what decides whether a trained
model's verdict is *learned* or *confounded*, so a design should be checked against it on a
development probe set before anything is trained. This scores ``--seeds`` random networks exactly
as the validity suite does (same control, every parameter random) and prints per concept the
accuracy of each and every cell whose confidence interval excludes 0.5 or that is learned
(the cells that would make a trained model's verdict *confounded*). The reference in
the same run is the untrained network (a constant: exactly 0.50 everywhere).

Usage: python bench/random_nets.py PROBES [--arch interaction] [--seeds 10]   (a development set)
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import pandas as pd

from voe.controls.random_nets import random_network
from voe.models.loading import load_model
from voe.report.build import build_report
from voe.scoring.score import score_probe_set
from voe.scoring.verdict import LEARNED


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("probes", type=Path)
    ap.add_argument("--arch", default="interaction")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args()
    out = a.out or Path(tempfile.mkdtemp(prefix="voe-random-nets-"))
    runs = []
    models = [random_network(a.arch, s) for s in range(a.seeds)]
    untrained = load_model(a.arch, {"seed": 0})
    untrained.name = f"untrained-{a.arch}"
    for m in [untrained, *models]:
        if not (out / m.name / "run.json").exists():
            score_probe_set(m, a.probes, out / m.name, model_ref=a.arch, batch_size=32, overwrite=True)
        runs.append(out / m.name)
    build_report(runs, out / "report", title=f"random {a.arch} networks", overwrite=True)
    s = pd.read_csv(out / "report" / "summary.csv")
    s["concept"] = s["concept"].str.split("-v").str[0].str[:8]
    print(f"random {a.arch} networks ({a.seeds} seeds, every parameter random) on {a.probes}; runs in {out}")
    print(s.pivot(index="model", columns="concept", values="accuracy").round(2).to_string())
    rand = s[~s["model"].str.startswith("untrained")]
    off = rand[(rand["ci_low"] > 0.5) | (rand["ci_high"] < 0.5) | (rand["verdict"] == LEARNED)]
    print("verdicts of the random networks:", rand.groupby("verdict").size().to_dict())
    print(f"cells off chance (CI without 0.5) or learned: {len(off)} of {len(rand)}"
          + "".join(f"\n  {r.model} x {r.concept}: {r.accuracy:.2f} [{r.ci_low:.2f}, {r.ci_high:.2f}] {r.verdict}"
                    for r in off.itertuples()))


if __name__ == "__main__":
    main()
