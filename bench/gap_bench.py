"""Benchmark the gap finder on recordings with a concealed effect (or none).

Usage: python bench/gap_bench.py [--cases 33] [--clean N] [--noise 0.001] [--jobs 2] [--truths a,b]
                                 [--episodes 12] [--duration 3] [--compound N] [--outside N]
                                 [--clean-kinds white,coloured] [--results runs/bench.jsonl [--score-only]]
Same code as ``voe gap bench``; prints a confusion matrix, the false-discovery rate on clean
recordings with its exact 95 % upper bound, parameter-recovery error and the median held-out
RMSE reduction. ``--cases`` cycle through every truth (``none`` included); ``--clean`` extra clean
cases are added on top (default: enough for 20 clean cases in all), and count only towards the
false-discovery rate.

``--results FILE`` appends each case's result to FILE as it finishes; run again with the same
arguments (and the same code) and only the missing cases run, so a run cut off by a stopped machine
resumes instead of starting over. ``--score-only`` prints the summary of the stored cases without
running any (``voe.gap.bench_store``).
"""

from __future__ import annotations

import argparse
import os
import time

from voe.errors import VoeError
from voe.gap.bench import NOISE_KINDS, TRUTHS, plan, run_bench
from voe.gap.bench_score import summary_lines
from voe.gap.bench_store import BenchStore


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
    ap.add_argument("--score-only", action="store_true", help="print the summary of the cases stored in --results; run none")
    a = ap.parse_args()
    t0 = time.perf_counter()
    truths = tuple(a.truths.split(","))
    run = {"cases": a.cases, "noise": a.noise, "seed": a.seed, "clean": a.clean, "truths": list(truths),
           "episodes": a.episodes, "duration": a.duration, "compound": a.compound, "outside": a.outside,
           "clean_kinds": a.clean_kinds.split(",")}
    try:
        store = BenchStore(a.results, run) if a.results else None
    except VoeError as exc:
        raise SystemExit(f"gap_bench: error: {exc}") from None
    if a.score_only:
        if store is None:
            raise SystemExit("gap_bench: error: --score-only needs --results FILE")
        rows = plan(a.cases, a.seed, a.clean, truths, a.compound, a.outside, tuple(a.clean_kinds.split(",")))
        results = [store.done[s] for s, _, _, _ in rows if s in store.done]
        print(f"scored from {a.results}: {len(results)} of {len(rows)} planned cases stored (none run now)")
        for line in summary_lines(results, a.noise):
            print(line)
        return
    results = run_bench(a.cases, a.noise, a.seed, a.jobs, clean=a.clean, truths=truths, episodes=a.episodes,
                        duration=a.duration, compound=a.compound, outside=a.outside,
                        clean_kinds=tuple(a.clean_kinds.split(",")), store=store, progress=lambda r: print(
        f"  case {r['seed']}: true {r['truth']:<26} {r['noise_kind']:<8} named {','.join(r['names']) or '-':<26} "
        f"{r['verdict']:<11} rmse {r['before']:.4g} -> {r['after']:.4g} param_err {r['param_error']:.3f} "
        f"covered {r['covered']}" + (f" dropped {','.join(r['dropped'])}" if r.get("dropped") else "")
        + (f" expressed {r['expressed'][0]}/{r['expressed'][1]}" if r.get("expressed") else ""), flush=True))
    for line in summary_lines(results, a.noise):
        print(line)
    print(f"wall time {time.perf_counter() - t0:.0f} s for {len(results)} cases (--jobs {a.jobs}, "
          f"load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
