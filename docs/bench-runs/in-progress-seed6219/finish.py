"""Write up seed 6219's untouched gap bench run once its last case is stored.

Run with the run's own venv and clone (the code the store was made by):

    PYTHONPATH=/work/untouched38 /work/venv38/bin/python finish_6219.py --session N [--main /work/main]

It refuses to do anything before all planned cases are stored. Then it
1. runs ``bench/gap_bench.py ... --score-only`` on the store (the summary as the bench prints it);
2. writes docs/bench-runs/gap_bench_sN_seed6219.txt (header, every case line in plan order, the summary)
   and .jsonl (the store's header and the last stored line of each case, in plan order);
3. git-mv's the in-progress folder's README to gap_bench_sN_seed6219_log.md and removes the folder;
4. replaces docs/gap.md's "Latest untouched run" block by this run's (session 36's block moves to the end of
   docs/bench-runs/README.md, links rewritten) and adds its row to the table.
The "Not met / Met" paragraph is left as NOTMET_PLACEHOLDER, to be written by hand from the case lines.
"""
from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

SEED = 6219  # --seed other than 6219 only to try this script on another finished store
ARGS = ["--cases", "130", "--clean", "180", "--compound", "8", "--outside", "12",
        "--clean-kinds", "coloured,white", "--jobs", "2"]
CLONE = Path("/work/untouched38")
STORE = Path("/work/runs/gap_6219.jsonl")
HEADER = Path("/work/runs/header_6219.txt")


def stored(store: Path) -> tuple[str, dict[int, str]]:
    """The store's header line and the last complete line of each case seed."""
    lines = store.read_text().split("\n")
    head, last = lines[0], {}
    for ln in lines[1:]:
        if not ln.strip():
            continue
        try:
            r = json.loads(ln)
        except json.JSONDecodeError:
            continue  # a line cut off by a stopped machine: the bench reran its case
        last[int(r["seed"])] = ln
    return head, last


def main() -> None:
    global SEED
    ap = argparse.ArgumentParser()
    ap.add_argument("--session", type=int, required=True)
    ap.add_argument("--main", type=Path, default=Path("/work/main"))
    ap.add_argument("--store", type=Path, default=STORE)
    ap.add_argument("--header", type=Path, default=HEADER)
    ap.add_argument("--seed", type=int, default=SEED)
    a = ap.parse_args()
    SEED = a.seed
    from voe.gap.bench_run import case_line, plan
    from voe.gap.bench_store import read_stores

    head, last = stored(a.store)
    run = json.loads(head)["run"]
    rows = plan(run["cases"], run["seed"], run["clean"], tuple(run["truths"]), run["compound"], run["outside"],
                tuple(run["clean_kinds"]))
    order = [s for s, _, _, _ in rows]
    missing = [s for s in order if s not in last]
    if missing:
        sys.exit(f"finish: {len(missing)} of {len(order)} planned cases not stored yet (first {missing[0]})")
    header = a.header.read_text()
    if "TODO" in header:
        sys.exit(f"finish: {a.header} still has a TODO line")
    out = subprocess.run([sys.executable, "bench/gap_bench.py", "--seed", str(SEED), *ARGS, "--results", str(a.store), "--score-only"],
                         cwd=CLONE, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"finish: --score-only failed ({out.returncode}): {out.stderr.strip()[-500:]}")
    summary = out.stdout.rstrip("\n").split("\n")
    n = a.session
    runs = a.main / "docs/bench-runs"
    stem = f"gap_bench_s{n}_seed{SEED}"
    done, _ = read_stores([str(a.store)], run)  # the records as the bench reads them (null -> nan)
    cases = [case_line(done[s]) for s in order]
    (runs / f"{stem}.txt").write_text(header.rstrip("\n") + "\n" + "\n".join(cases + summary) + "\n")
    (runs / f"{stem}.jsonl").write_text("\n".join([head] + [last[s] for s in order]) + "\n")
    folder = runs / f"in-progress-seed{SEED}"
    git = ["git", "-C", str(a.main)]
    subprocess.run([*git, "mv", str(folder / "README.md"), str(runs / f"{stem}_log.md")], check=True)
    subprocess.run([*git, "rm", "-rq", str(folder)], check=True)
    log = runs / f"{stem}_log.md"  # its links to the folder's scripts and patch, gone with the folder, become names
    log.write_text(re.sub(r"\[([^\]]+)\]\(([^)\s:#]+)\)",
                          lambda m: m.group(0) if (log.parent / m.group(2)).exists() else f"`{m.group(1)}`",
                          log.read_text()))
    readme(a.main, n, summary)
    print(f"finish: wrote {stem}.txt/.jsonl/_log.md and the docs/gap.md block; fill NOTMET_PLACEHOLDER by hand")


LINK = re.compile(r"\]\(([^)\s]+)\)")


def from_bench_runs(m: re.Match) -> str:
    """A link written in docs/gap.md, rewritten to work from docs/bench-runs/README.md."""
    t = m.group(1)
    if re.match(r"[a-z]+:", t) or t.startswith("#"):
        return m.group(0)
    if t.startswith("bench-runs/"):
        return f"]({t[len('bench-runs/'):]})"
    return f"](../{t})"


def pick(summary: list[str], prefix: str) -> str:
    hits = [s for s in summary if s.startswith(prefix)]
    if len(hits) != 1:
        sys.exit(f"finish: summary line {prefix!r} found {len(hits)} times")
    return hits[0]


def readme(main: Path, n: int, summary: list[str]) -> None:
    """Swap docs/gap.md's latest-run block for this run's and add its table row (links relative to docs/)."""
    path = main / "docs/gap.md"
    text = path.read_text()
    start = text.index("**Latest untouched run of the default finder (sessions 34-36, seed 8367)")
    cut = text.index("Seed 8367 is development from session 36 on.", start) + len("Seed 8367 is development from session 36 on.")
    end = text.index("**Every untouched run so far**", start)
    old36 = text[start:cut].strip()
    s38 = text[cut:end].strip()  # session 38's paragraph: what the measured code is
    s38 = re.sub(r" Main's own untouched run, seed 6219, is in\s+progress:.*$", "", s38, flags=re.S).strip()
    body = summary[summary.index(next(s for s in summary if s.startswith("gap bench: "))):]
    met = pick(body, "targets met: ")
    k = int(re.match(r"targets met: (\d+) of 10", met).group(1))
    log = (main / f"docs/bench-runs/gap_bench_s{n}_seed{SEED}_log.md").read_text()
    block = (
        f"**Latest untouched run of the default finder (sessions 38-{n}, seed {SEED}): {k} of 10 targets.** `python\n"
        f"bench/gap_bench.py --cases 130 --clean 180 --compound 8 --outside 12 --clean-kinds coloured,white --seed {SEED}\n"
        f"--jobs 2 --results runs/gap_{SEED}.jsonl` (330 cases; seed {SEED} drawn with `secrets` at 09:43:07 UTC on\n"
        "2026-11-30 in session 37 before any run, and run once, from fresh clones of main at 3701bfd: session 37's\n"
        "second-look test-gain bar and session 38's sparse-then-dense fit step). It ran across several sessions,\n"
        "each resuming the same store from a clone at 3701bfd (its starts and stops are in the log below); no voe\n"
        "source changed on main while it ran. Chosen on the development seeds 0-99, 5151, 6263, 7741, 3629, 1531,\n"
        "8586, 7857, 8587, 5250, 4593, 2758, 4446, 9028, 6157, 6685, 1078, 1967, 2250, 2307, 6774 and 8367.\n"
        "Every case line, the summary and the store:\n"
        f"[docs/bench-runs/gap_bench_s{n}_seed{SEED}.txt](bench-runs/gap_bench_s{n}_seed{SEED}.txt),\n"
        f"[docs/bench-runs/gap_bench_s{n}_seed{SEED}.jsonl](bench-runs/gap_bench_s{n}_seed{SEED}.jsonl); its log of\n"
        "starts and stops (and a slip: two stored case lines seen in session 39 before the end):\n"
        f"[docs/bench-runs/gap_bench_s{n}_seed{SEED}_log.md](bench-runs/gap_bench_s{n}_seed{SEED}_log.md).\n\n"
        "```\n" + "\n".join(body) + "\n```\n\n"
        + s38 + "\n\nNOTMET_PLACEHOLDER\n\n")
    assert "Log of starts and stops" in log
    text = text[:start] + block + text[end:]
    # the table's new row, above session 36's
    single = pick(body, "single-effect identification")
    m = re.search(r"(\d+/\d+ = [\d.]+ %) \(95 % CI ([\d.]+)-([\d.]+) %", single)
    ci = f"({round(float(m.group(2)))}-{round(float(m.group(3)))})"
    comp = re.search(r"(\d+/\d+) = ", pick(body, "compound truths")).group(1)
    ool = pick(body, "out-of-library truths")
    mis = re.search(r"misnamed as a library effect (\d+/\d+)", ool).group(1)
    rest = re.search(r"unexplained and located (\d+/\d+)", ool).group(1)

    def fd(kind: str) -> str:
        line = pick(body, f"false discovery on clean ({kind} noise):")
        frac = re.search(r"(\d+/\d+) = ", line).group(1)
        bound = float(re.search(r"upper bound ([\d.]+) %", line).group(1))
        return frac + (f" (bound {bound} %)" if bound > 8 else "")

    row = (f"| {n} (default: second-look test gain, sparse-then-dense fit step) | {SEED} | {m.group(1)} {ci} | {comp} | "
           f"{mis} | {rest} | {fd('coloured')} | {fd('white')} |\n")
    anchor = "| 36 (default: second look,"
    i = text.index(anchor)
    text = text[:i] + row + text[i:]
    text = text.replace("the blocks of sessions 11-32, with their misses", "the blocks of sessions 11-36, with their misses", 1)
    path.write_text(text)
    # session 36's block to docs/bench-runs/README.md, links rewritten to work from that folder
    runs_readme = main / "docs/bench-runs/README.md"
    moved = LINK.sub(from_bench_runs, old36)
    rt = runs_readme.read_text()
    rt = rt.replace("# Untouched gap bench runs, sessions 11-32", "# Untouched gap bench runs, sessions 11-36", 1)
    rt = (rt.rstrip("\n") + f"\n\nSession 36's block, moved here from docs/gap.md in session {n} (verbatim but for links), "
          f"when seed {SEED}'s run took its place:\n\n" + moved + "\n")
    runs_readme.write_text(rt)


if __name__ == "__main__":
    main()
