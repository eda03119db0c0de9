"""Benchmark the gap finder on recordings with a concealed effect (or none).

Usage: python bench/gap_bench.py [--cases 33] [--clean N] [--noise 0.001] [--jobs 2] [--truths a,b]
                                 [--episodes 12] [--duration 3] [--compound N] [--outside N]
                                 [--clean-kinds white,coloured] [--results runs/bench.jsonl [--score-only]]
                                 [--cross-fit]
Same code as ``voe gap bench`` (``voe.gap.bench_run``); prints a confusion matrix, the
false-discovery rate on clean recordings with its exact 95 % upper bound, parameter-recovery error
and the median held-out RMSE reduction. ``--cases`` cycle through every truth (``none`` included);
``--clean`` extra clean cases are added on top (default: enough for 20 clean cases in all), and
count only towards the false-discovery rate.

``--results FILE`` appends each case's result to FILE as it finishes; run again with the same
arguments (and the same code) and only the missing cases run, so a run cut off by a stopped machine
resumes instead of starting over (the stored cases' lines are not printed again, so an untouched
run is not read before it ends; the summary covers them). ``--score-only`` prints the summary of the stored cases without
running any (``voe.gap.bench_store``). ``--shard I/N`` runs every N-th case from the I-th, so a
SLURM job array spreads one run over nodes (``--shard $SLURM_ARRAY_TASK_ID/N --results
runs/b.$SLURM_ARRAY_TASK_ID.jsonl``); ``--score-only --results runs/b.0.jsonl,runs/b.1.jsonl,...``
then prints the whole run's summary.
"""

from __future__ import annotations

import argparse

from voe.errors import VoeError
from voe.gap.bench import NOISE_KINDS, TRUTHS
from voe.gap.bench_run import BenchRun, bench_command


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--cases", type=int, default=33)
    ap.add_argument("--noise", type=float, default=1e-3)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--clean", type=int, default=None, help="extra clean cases (default: up to 20 clean in all)")
    ap.add_argument("--truths", default=",".join(TRUTHS), help="comma-separated truths to cycle through")
    ap.add_argument("--episodes", type=int, default=12, help="episodes per case (the finder splits them half fitting, a third selection, a sixth test)")
    ap.add_argument("--duration", type=float, default=3.0, help="seconds per episode")
    ap.add_argument("--compound", type=int, default=0, help="cases cycling through the compound truths")
    ap.add_argument("--outside", type=int, default=0, help="cases cycling through the out-of-library truths")
    ap.add_argument("--clean-kinds", default="white,coloured", help=f"noise of the extra clean cases, from {NOISE_KINDS}")
    ap.add_argument("--results", default=None, help="JSON-lines file the case results are appended to (and resumed from)")
    ap.add_argument("--score-only", action="store_true", help="print the summary of the cases stored in --results "
                    "(FILE,FILE,...: the shards of one run); run none")
    ap.add_argument("--cross-fit", action="store_true", help="the finder cross-fits: the non-test episodes' halves "
                    "swap fitting and selection (twice the fitting work; GapConfig.cross_fit)")
    ap.add_argument("--shard", default=None, help="I/N: run part I of N only, e.g. $SLURM_ARRAY_TASK_ID/8 (one --results file each)")
    a = ap.parse_args()
    try:
        run = BenchRun(cases=a.cases, noise=a.noise, seed=a.seed, clean=a.clean, truths=tuple(a.truths.split(",")),
                       episodes=a.episodes, duration=a.duration, compound=a.compound, outside=a.outside,
                       clean_kinds=tuple(a.clean_kinds.split(",")), cross_fit=a.cross_fit)
        bench_command(run, a.jobs, a.results, a.score_only, a.shard, echo=lambda s: print(s, flush=True))
    except VoeError as exc:
        raise SystemExit(f"gap_bench: error: {exc}") from None


if __name__ == "__main__":
    main()
