"""Write up seed 6191's untouched gap bench run once its last case is stored.

Run with the run's own venv and clone (the code the store was made by), after filling header.txt's TODOs:

    PYTHONPATH=<clone> <venv>/bin/python finish.py --session N --clone <clone> --store ../runs/gap_6191.jsonl \
        --header header.txt [--main /work/main]

(copy this script and header.txt out of this folder first: step 3 removes the folder). It refuses to do
anything before all planned cases are stored. Then it
1. runs ``bench/gap_bench.py ... --score-only`` in the clone on the store (the summary as the bench prints it);
2. writes docs/bench-runs/gap_bench_sN_seed6191.txt (header, every case line in plan order, the summary)
   and .jsonl (the store's header and the last stored line of each case, in plan order);
3. git-mv's this folder's README to gap_bench_sN_seed6191_log.md and removes the folder;
4. replaces docs/gap.md's "Latest untouched run" block (and the in-progress paragraph after it) by this run's,
   moves the block it replaces to the end of docs/bench-runs/README.md (links rewritten) and adds the run's
   row to the table.
The "Not met / Met" paragraph is left as NOTMET_PLACEHOLDER, to be written by hand from the case lines.
The script that wrote seed 9404's run up in session 67 (``gap_bench_s67_seed9404.*``; before it, seeds 5905, 2276, 3829, 6056,
4497, 1829, 9260, 3511, 7241, 5025, 8657, 1066 and 6219), with this run's seed, sessions, commit and description as its
defaults; the latest block's heading is read as "session N" or "sessions N-M" (seed 9404's reads "sessions 66-67").
"""
from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import textwrap
from pathlib import Path

ARGS = ["--cases", "130", "--clean", "180", "--compound", "8", "--outside", "12",
        "--clean-kinds", "coloured,white", "--jobs", "2"]
LATEST = re.compile(r"\*\*Latest untouched run of the default finder \(sessions? (\d+)(?:-(\d+))?, seed (\d+)\)")
IN_PROGRESS = "Main's own untouched run of the finder"
TABLE = "**Every untouched run so far**"
LINK = re.compile(r"\]\(([^)\s]+)\)")


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
    ap = argparse.ArgumentParser()
    ap.add_argument("--session", type=int, required=True, help="the session that finishes the run")
    ap.add_argument("--clone", type=Path, required=True, help="a clone at the run's commit")
    ap.add_argument("--store", type=Path, required=True)
    ap.add_argument("--header", type=Path, required=True)
    ap.add_argument("--main", type=Path, default=Path("/work/main"))
    ap.add_argument("--seed", type=int, default=6191)
    ap.add_argument("--first-session", type=int, default=68)
    ap.add_argument("--code", default="c89668c")
    ap.add_argument("--drawn", default="05:38 UTC on\n2026-12-05 in session 68")
    ap.add_argument("--what", default="no round offers, and the re-selection does not ask, a `mass` that would put one on every body while every part of the model is mass-proportional (`voe.gap.mass_ratio`), and a drop that leaves exactly the parts the search accepted earlier reports the search's own earlier model", help="what the measured code added, for the block's first paragraph")
    ap.add_argument("--row", default="default: no mass on every body; the check's earlier model", help="the table row's description")
    a = ap.parse_args()
    from voe.gap.bench_run import case_line, plan
    from voe.gap.bench_store import read_stores

    head, last = stored(a.store)
    run = json.loads(head)["run"]
    if run["seed"] != a.seed:
        sys.exit(f"finish: {a.store} is seed {run['seed']}'s store, not {a.seed}'s")
    rows = plan(run["cases"], run["seed"], run["clean"], tuple(run["truths"]), run["compound"], run["outside"],
                tuple(run["clean_kinds"]))
    order = [s for s, _, _, _ in rows]
    missing = [s for s in order if s not in last]
    if missing:
        sys.exit(f"finish: {len(missing)} of {len(order)} planned cases not stored yet (first {missing[0]})")
    header = a.header.read_text()
    if "TODO" in header:
        sys.exit(f"finish: {a.header} still has a TODO line")
    out = subprocess.run([sys.executable, "bench/gap_bench.py", "--seed", str(a.seed), *ARGS, "--results",
                          str(a.store.resolve()), "--score-only"], cwd=a.clone, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"finish: --score-only failed ({out.returncode}): {out.stderr.strip()[-500:]}")
    summary = out.stdout.rstrip("\n").split("\n")
    n = a.session
    runs = a.main / "docs/bench-runs"
    stem = f"gap_bench_s{n}_seed{a.seed}"
    done, _ = read_stores([str(a.store)], run)  # the records as the bench reads them (null -> nan)
    cases = [case_line(done[s]) for s in order]
    (runs / f"{stem}.txt").write_text(header.rstrip("\n") + "\n" + "\n".join(cases + summary) + "\n")
    (runs / f"{stem}.jsonl").write_text("\n".join([head] + [last[s] for s in order]) + "\n")
    folder = runs / f"in-progress-seed{a.seed}"
    git = ["git", "-C", str(a.main)]
    subprocess.run([*git, "mv", str(folder / "README.md"), str(runs / f"{stem}_log.md")], check=True)
    subprocess.run([*git, "rm", "-rqf", str(folder)], check=True)
    log = runs / f"{stem}_log.md"  # its links to the folder's scripts, gone with the folder, become names
    log.write_text(re.sub(r"\[([^\]]+)\]\(([^)\s:#]+)\)",
                          lambda m: m.group(0) if (log.parent / m.group(2)).exists() else f"`{m.group(1)}`",
                          log.read_text()))
    readme(a, summary)
    print(f"finish: wrote {stem}.txt/.jsonl/_log.md and the docs/gap.md block; fill NOTMET_PLACEHOLDER by hand")


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


def readme(a: argparse.Namespace, summary: list[str]) -> None:
    """Swap docs/gap.md's latest-run block for this run's and add its table row (links relative to docs/)."""
    n, seed = a.session, a.seed
    path = a.main / "docs/gap.md"
    text = path.read_text()
    m0 = LATEST.search(text)
    if m0 is None:
        sys.exit("finish: docs/gap.md has no 'Latest untouched run' block")
    start, prev_end, prev_seed = m0.start(), int(m0.group(2) or m0.group(1)), int(m0.group(3))
    end = text.index(TABLE, start)
    cut = text.find(IN_PROGRESS, start, end)
    old = text[start:cut if cut >= 0 else end].strip()
    body = summary[summary.index(next(s for s in summary if s.startswith("gap bench: "))):]
    k = int(re.match(r"targets met: (\d+) of 10", pick(body, "targets met: ")).group(1))
    stem = f"bench-runs/gap_bench_s{n}_seed{seed}"
    para = (
        f"**Latest untouched run of the default finder (sessions {a.first_session}-{n}, seed {seed}): {k} of 10 "
        f"targets.** `python bench/gap_bench.py --cases 130 --clean 180 --compound 8 --outside 12 --clean-kinds "
        f"coloured,white --seed {seed} --jobs 2 --results runs/gap_{seed}.jsonl` (330 cases; seed {seed} drawn with "
        f"`secrets` at {a.drawn} after the code it measures had landed and before any run, and run once, from "
        f"clones of main at {a.code}: {a.what}). It ran across several sessions, each resuming the same store from "
        f"a clone at {a.code} (its starts and stops are in the log below); no voe source changed on main while it "
        f"ran. Seed {prev_seed} became a development seed before this one was drawn. Every case line, the summary "
        f"and the store: [docs/{stem}.txt]({stem}.txt), [docs/{stem}.jsonl]({stem}.jsonl); its log of starts and "
        f"stops: [docs/{stem}_log.md]({stem}_log.md).")
    block = (
        textwrap.fill(para.replace("\n", " "), 110, break_on_hyphens=False, break_long_words=False)
        + "\n\n```\n" + "\n".join(body) + "\n```\n\nNOTMET_PLACEHOLDER\n\n")
    text = text[:start] + block + text[end:]
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

    row = (f"| {n} ({a.row}) | {seed} | {m.group(1)} {ci} | {comp} | {mis} | {rest} | {fd('coloured')} | "
           f"{fd('white')} |\n")
    anchor = re.search(rf"^\| {prev_end} \(", text, flags=re.M)
    if anchor is None:
        sys.exit(f"finish: docs/gap.md's table has no row for session {prev_end}")
    text = text[:anchor.start()] + row + text[anchor.start():]
    text = re.sub(r"the blocks of sessions 11-(\d+), with their misses", f"the blocks of sessions 11-{prev_end}, "
                  "with their misses", text, count=1)
    path.write_text(text)
    runs_readme = a.main / "docs/bench-runs/README.md"
    rt = re.sub(r"^# Untouched gap bench runs, sessions 11-\d+", f"# Untouched gap bench runs, sessions 11-{prev_end}",
                runs_readme.read_text(), count=1)
    rt = (rt.rstrip("\n") + f"\n\nSession {prev_end}'s block, moved here from docs/gap.md in session {n} (verbatim "
          f"but for links), when seed {seed}'s run took its place:\n\n" + LINK.sub(from_bench_runs, old) + "\n")
    runs_readme.write_text(rt)


if __name__ == "__main__":
    main()
