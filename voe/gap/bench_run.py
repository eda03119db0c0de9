"""The gap bench as a command: run (or resume) the cases, print a line per case and the summary.

Why one place: ``bench/gap_bench.py`` (the form docs/gap.md's untouched runs quote) and
``voe gap bench`` (the CLI) used to parse their own options and print their own case lines, and
the CLI had lost the compound, out-of-library, clean-noise and store options. Both now call
``bench_command``, so the two print the same lines for the same arguments.
"""

from __future__ import annotations

import difflib
import os
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

from voe.errors import DataError, UnknownNameError
from voe.gap.bench import NOISE_KINDS, TRUTHS, plan, run_bench
from voe.gap.bench_score import summary_lines
from voe.gap.bench_store import BenchStore, code_hash, read_stores
from voe.parallel import parse_shard


@dataclass(frozen=True)
class BenchRun:
    """The arguments that fix a bench run's cases and their outcome (``jobs`` does not).

    ``cases`` cycle through ``truths`` (``none`` included); ``compound`` and ``outside`` cycle
    through the two-effect and out-of-library truths; ``clean`` extra clean cases (None: enough
    for 20 clean in all) cycle through ``clean_kinds`` noise.
    """

    cases: int = 33
    noise: float = 1e-3
    seed: int = 0
    clean: int | None = None
    truths: tuple[str, ...] = TRUTHS
    episodes: int = 12
    duration: float = 3.0
    compound: int = 0
    outside: int = 0
    clean_kinds: tuple[str, ...] = ("white", "coloured")
    cross_fit: bool = False  # the finder cross-fits (``GapConfig.cross_fit``)

    def __post_init__(self) -> None:
        for kind, names, known in (("truth", self.truths, TRUTHS), ("noise kind", self.clean_kinds, NOISE_KINDS)):
            for n in names:
                if n not in known:
                    close = difflib.get_close_matches(n, known, n=3, cutoff=0.5)
                    hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
                    raise UnknownNameError(f"unknown bench {kind} '{n}'{hint} (known: {', '.join(known)})")

    def store_key(self) -> dict:
        """The run's arguments as stored in a results file's header (``cross_fit`` only when set,
        so stores made before the option existed still match their runs)."""
        key = {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}
        if not key["cross_fit"]:
            del key["cross_fit"]
        return key


def case_line(r: dict) -> str:
    """One case as the bench prints it (the untouched runs' case files are these lines)."""
    return (f"  case {r['seed']}: true {r['truth']:<26} {r['noise_kind']:<8} named {','.join(r['names']) or '-':<26} "
            f"{r['verdict']:<11} rmse {r['before']:.4g} -> {r['after']:.4g} param_err {r['param_error']:.3f} "
            f"covered {r['covered']}" + (f" dropped {','.join(r['dropped'])}" if r.get("dropped") else "")
            + (f" expressed {r['expressed'][0]}/{r['expressed'][1]}" if r.get("expressed") else ""))


def bench_command(run: BenchRun, jobs: int = 1, results: str | None = None, score_only: bool = False,
                  shard: str | None = None, echo: Callable[[str], None] = print) -> list[dict]:
    """Run ``run`` (resuming from the store ``results`` if given) or, with ``score_only``, score
    the cases stored in ``results`` (comma-separated files: the shards of one run); ``echo`` each
    case line and the summary. Returns the results.

    ``shard`` ``"I/N"``: run part I of N only (a SLURM array task: ``--shard $SLURM_ARRAY_TASK_ID/N``,
    each task with its own ``--results`` file); its summary covers its own cases only.

    Raises:
        DataError: a store made by other code or arguments, ``score_only`` without one, or several
            stores for one running shard.
    """
    t0 = time.perf_counter()
    files = [f for f in (results or "").split(",") if f]
    part = parse_shard(shard) if shard else None
    if score_only:
        if not files:
            raise DataError("gap bench: --score-only needs --results FILE[,FILE...]")
        if part is not None:
            raise DataError("gap bench: --score-only scores every shard's file together; drop --shard")
        done, codes = read_stores(files, run.store_key())
        rows = plan(run.cases, run.seed, run.clean, run.truths, run.compound, run.outside, run.clean_kinds)
        out = [done[s] for s, _, _, _ in rows if s in done]
        here = code_hash()
        echo(f"scored from {', '.join(files)}: {len(out)} of {len(rows)} planned cases stored (none run now), made by "
             f"voe sources sha256 {', '.join(sorted({c[:12] for c in codes}))}"
             + ("" if set(codes) == {here} else f" (this code: {here[:12]})"))
    else:
        if len(files) > 1:
            raise DataError("gap bench: a running bench stores into one --results file (one per --shard)")
        store = BenchStore(files[0], run.store_key(), shard=part) if files else None
        if store is not None and store.done:
            # a run read before its end could steer the code it measures: the stored cases' lines
            # were printed when they ran, and --score-only scores them; a resume does not show them
            echo(f"resumed from {files[0]}: {len(store.done)} cases stored, their lines not shown again")
        out = run_bench(run.cases, run.noise, run.seed, jobs, clean=run.clean, truths=run.truths,
                        episodes=run.episodes, duration=run.duration, compound=run.compound, outside=run.outside,
                        clean_kinds=run.clean_kinds, store=store, shard=part, progress=lambda r: echo(case_line(r)),
                        cross_fit=run.cross_fit, show_stored=False)
    if part is not None:
        echo(f"shard {part[0]}/{part[1]}: {len(out)} cases; score every shard's file together with "
             "--score-only --results FILE,FILE,...")
    for line in summary_lines(out, run.noise):
        echo(line)
    if not score_only:
        echo(f"wall time {time.perf_counter() - t0:.0f} s for {len(out)} cases (--jobs {jobs}, "
             f"load average {os.getloadavg()[0]:.1f})")
    return out
