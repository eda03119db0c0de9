"""Rescore a stored gap bench run with this code's location stage (departure test, timing jitter)
for every case that named nothing: ``python bench/gap_relocate.py RESULTS.jsonl [--out NEW.jsonl]``.

Why: an untouched bench run takes hours, and a change to the departure test reaches only the
verdict of the cases that named nothing; for those, rerunning the location as the finder runs it
gives exactly the verdict this code would give (``voe.gap.bench_relocate``, which checks that the
rest of the location is unchanged and refuses otherwise). Cases that named an effect keep their
stored result. The summary and target lines are printed as the bench prints them.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from tqdm import tqdm

from voe.errors import VoeError
from voe.gap.bench_relocate import relocate
from voe.gap.bench_score import summary_lines
from voe.gap.bench_store import BenchStore, code_hash
from voe.io import jsonio
from voe.io.atomic import atomic_write_text


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", help="a bench store (bench/gap_bench.py --results), complete")
    ap.add_argument("--out", default=None, help="write the rescored cases here (JSON lines, the header first)")
    a = ap.parse_args()
    try:
        head = json.loads(Path(a.results).read_text().split("\n", 1)[0])
        store = BenchStore(a.results, head["run"], read_only=True)
    except (VoeError, OSError, ValueError, KeyError) as exc:
        raise SystemExit(f"gap_relocate: error: {a.results}: {exc}") from None
    run = head["run"]
    out, changed = [], 0
    for r in tqdm([store.done[k] for k in sorted(store.done)], desc="relocate", file=sys.stderr):
        try:
            new = relocate(r, run) if r["n_effects"] == 0 and r["verdict"] != "error" else r
        except VoeError as exc:
            raise SystemExit(f"gap_relocate: error: {a.results}: {exc}") from None
        if new["verdict"] != r["verdict"]:
            changed += 1
            print(f"  case {r['seed']}: {r['truth']} {r['noise_kind']}: {r['verdict']} -> {new['verdict']} "
                  f"(departure p {new['relocated']:.3g})", flush=True)
        out.append(new)
    print(f"relocated {sum('relocated' in r for r in out)} of {len(out)} stored cases (those that named nothing) "
          f"with voe sources sha256 {code_hash()[:12]} (stored: {(store.made_by or '')[:12]}); {changed} verdicts changed")
    for line in summary_lines(out, run["noise"]):
        print(line)
    if a.out:
        atomic_write_text(Path(a.out), "\n".join([jsonio.dumps({**head, "relocated_by": code_hash()})]
                                                 + [jsonio.dumps(r) for r in out]) + "\n")


if __name__ == "__main__":
    main()
