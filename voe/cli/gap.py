"""``voe gap``: diagnose a sim-to-real gap, or benchmark the finder on concealed effects.

Why a fallback group: ``voe gap SCENE RECORDINGS --out DIR`` is the everyday form, while
``voe gap bench`` is a subcommand. ``_DefaultGroup`` routes any first argument that is not a
subcommand name to ``diagnose``, so both forms work and ``voe gap diagnose ...`` does too.
"""

from __future__ import annotations

from pathlib import Path

import typer
from typer.core import TyperGroup

from voe.cli.common import claims_output


class _DefaultGroup(TyperGroup):
    def parse_args(self, ctx, args):  # noqa: ANN001 - click signature
        if args and args[0] not in self.commands and args[0] not in ("--help", "-h"):
            args = ["diagnose", *args]
        return super().parse_args(ctx, args)


app = typer.Typer(cls=_DefaultGroup, help="Find what a nominal pymunk scene leaves out, from recordings.",
                  no_args_is_help=True, add_completion=False)


@app.command("diagnose")
@claims_output("dir", replaces=("gap.json",))
def diagnose_cmd(
    scene: Path = typer.Argument(..., help="scene.json"),
    recordings: Path = typer.Argument(..., help="recordings (.csv or .parquet)"),
    out: Path = typer.Option(..., "--out", help="output directory for gap.json and gap.md"),
    effects: str = typer.Option("", "--effects", help="comma-separated effect names (default: all)"),
    max_effects: int = typer.Option(3, "--max-effects"),
    seed: int = typer.Option(0, "--seed"),
    no_figures: bool = typer.Option(False, "--no-figures", help="write gap.md without its figures"),
    jobs: int = typer.Option(2, "--jobs", min=1, help="processes fitting candidates in parallel (same result)"),
    cross_fit: bool = typer.Option(False, "--cross-fit", help="halves of the non-test episodes swap fitting and "
                                   "selection: more evidence for effects felt in few windows, twice the fitting work"),
    second_look: bool = typer.Option(True, "--second-look/--no-second-look", help="when the three-way split names "
                                     "nothing, look again cross-fitted (GapConfig.second_look)"),
) -> None:
    """Locate the mismatch, name and fit the missing effects, verify on held-out episodes."""
    from tqdm import tqdm

    from voe.gap.run import diagnose
    from voe.gap.stages import GapConfig

    names = [e.strip() for e in effects.split(",") if e.strip()] or None
    with tqdm(desc="voe gap", unit="step", leave=False) as bar:
        def progress(msg: str) -> None:
            bar.set_postfix_str(msg)
            bar.update(1)

        def total(n: int) -> None:  # the most steps there can be: the search may stop early
            bar.total = n
            bar.refresh()

        config = GapConfig(cross_fit=cross_fit, second_look=second_look)
        finder = diagnose(scene, recordings, out, names, max_effects, seed, config=config,
                          figures=not no_figures, progress=progress, n_jobs=jobs, total=total)
    typer.echo(f"verdict: {finder.verdict_}")
    typer.echo(finder.explanation_)
    typer.echo(f"wrote {out / 'gap.json'}")


@app.command("bench")
def bench_cmd(
    cases: int = typer.Option(22, "--cases", help="cases cycling through the single truths (none included)"),
    noise: float = typer.Option(0.001, "--noise", help="position noise in m"),
    seed: int = typer.Option(0, "--seed"),
    jobs: int = typer.Option(1, "--jobs", min=1, help="worker processes"),
    clean: int = typer.Option(None, "--clean", help="extra clean cases (default: up to 20 clean in all)"),
    truths: str = typer.Option("", "--truths", help="comma-separated single truths to cycle through (default: all)"),
    episodes: int = typer.Option(12, "--episodes", help="episodes per case"),
    duration: float = typer.Option(3.0, "--duration", help="seconds per episode"),
    compound: int = typer.Option(0, "--compound", help="cases cycling through the two-effect truths"),
    outside: int = typer.Option(0, "--outside", help="cases cycling through the out-of-library truths"),
    clean_kinds: str = typer.Option("white,coloured", "--clean-kinds", help="noise of the extra clean cases"),
    results: str = typer.Option(None, "--results", help="JSON-lines store: each case appended as it ends; a rerun resumes"),
    score_only: bool = typer.Option(False, "--score-only", help="print the summary of the cases in --results "
                                    "(FILE,FILE,...: the shards of one run); run none"),
    shard: str = typer.Option(None, "--shard", help="I/N: run part I of N only (a SLURM array task: "
                              "$SLURM_ARRAY_TASK_ID/N), one --results file per shard"),
    cross_fit: bool = typer.Option(False, "--cross-fit", help="the finder cross-fits (GapConfig.cross_fit)"),
) -> None:
    """Benchmark identification on recordings with a concealed random effect (or none)."""
    from voe.gap.bench import TRUTHS
    from voe.gap.bench_run import BenchRun, bench_command

    run = BenchRun(cases=cases, noise=noise, seed=seed, clean=clean,
                   truths=tuple(t.strip() for t in truths.split(",") if t.strip()) or TRUTHS,
                   episodes=episodes, duration=duration, compound=compound, outside=outside,
                   clean_kinds=tuple(k.strip() for k in clean_kinds.split(",") if k.strip()), cross_fit=cross_fit)
    bench_command(run, jobs, results, score_only, shard, echo=typer.echo)
