"""Does the blind harness defeat scorers that cheat? Old harness vs blind harness, per concept.

For each cheater in ``voe.testing`` (reads the clip ids, uses the batch position, peeks at the
future) it prints matched-set accuracy per concept twice: under the old harness (role-bearing
clip ids, each matched set scored together in stored order; the reference, measured in the same
run) and under the blind harness (``score_probe_set``: opaque keys, shuffled order, one clip of a
set per batch; scored *without* the pre-run check). Then the check that ``check_model`` rejects
each cheater with. The honest ``RandomModel`` is the chance reference.

Usage::

    voe probes generate --concepts core --n 20 --seed 0 --out /tmp/probes   # or let the bench make one
    python bench/blind_bench.py --probes /tmp/probes
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from voe.errors import ModelContractError
from voe.io.probeset import load_probe_set
from voe.models.check import check_model
from voe.scoring import load_run
from voe.scoring.metrics import score_set
from voe.scoring.order import Blinder, plan
from voe.scoring.score import score_probe_set
from voe.scoring.table import concept_table
from voe.testing import FuturePeekingModel, IdReaderModel, PositionModel, RandomModel


def old_harness(model, ps) -> dict[str, float]:
    """Accuracy per concept when each set is one batch in stored order with its real clip ids."""
    out = {}
    for concept, grp in ps.index.sort_values("row").groupby("concept"):
        acc = []
        for _, s in grp.groupby("set_id", sort=True):
            nll = model.frame_nll(ps.batch(list(s["clip_id"])))
            acc.append(score_set(nll, (s["role"] == "impossible").to_numpy()).accuracy)
        out[concept] = float(np.mean(acc))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--probes", type=Path, help="probe set (default: generate N sets per core concept)")
    ap.add_argument("--n", type=int, default=20, help="sets per concept when generating")
    ap.add_argument("--batch-size", type=int, default=16)
    args = ap.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="voe-blind-bench-"))
    probes = args.probes
    if probes is None:
        from voe.concepts import CONCEPTS
        from voe.concepts.generate import generate_probe_set
        from voe.sim.scene import SimConfig

        probes = tmp / "probes"
        t0 = time.perf_counter()
        generate_probe_set(probes, CONCEPTS.ids(), args.n, 0, SimConfig(), jobs=2)
        print(f"generated {args.n} sets per concept in {time.perf_counter() - t0:.0f} s")
    ps = load_probe_set(probes)
    blinder = Blinder(ps)
    sample = blinder.batch(blinder.sample(plan(ps.index, 6), 6))
    concepts = sorted(ps.index["concept"].unique())
    print(f"{len(ps)} clips, {ps.index['set_id'].nunique()} matched sets, {len(concepts)} concepts\n")
    print(f"{'scorer':<15} {'harness':<7} " + " ".join(f"{c.split('-v')[0][:11]:>11}" for c in concepts))
    for model in (IdReaderModel(), PositionModel(), FuturePeekingModel(), RandomModel()):
        old = old_harness(model, ps)
        run = tmp / model.name
        score_probe_set(model, ps, run, batch_size=args.batch_size)
        t = concept_table([load_run(run)], n_boot=2000).set_index("concept")
        print(f"{model.name:<15} {'old':<7} " + " ".join(f"{old[c]:>11.2f}" for c in concepts))
        print(f"{'':<15} {'blind':<7} " + " ".join(f"{t.loc[c, 'accuracy']:>11.2f}" for c in concepts))
        ci = " ".join(f"{t.loc[c, 'ci_low']:>5.2f}-{t.loc[c, 'ci_high']:<5.2f}" for c in concepts)
        print(f"{'':<15} {'95% CI':<7} {ci}")
        print(f"{'':<15} {'verdict':<7} " + " ".join(f"{t.loc[c, 'verdict'][:11]:>11}" for c in concepts))
        try:
            check_model(model, sample)
            print(f"{'':<15} check_model: passes\n")
        except ModelContractError as exc:
            print(f"{'':<15} check_model: {str(exc).split(':')[0].split('failed ')[-1]}\n")


if __name__ == "__main__":
    main()
