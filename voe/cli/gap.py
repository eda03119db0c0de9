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
) -> None:
    """Locate the mismatch, name and fit the missing effects, verify on held-out episodes."""
    from tqdm import tqdm

    from voe.gap.run import diagnose

    names = [e.strip() for e in effects.split(",") if e.strip()] or None
    with tqdm(desc="voe gap", unit="step", leave=False) as bar:
        def progress(msg: str) -> None:
            bar.set_postfix_str(msg)
            bar.update(1)

        def total(n: int) -> None:  # the most steps there can be: the search may stop early
            bar.total = n
            bar.refresh()

        finder = diagnose(scene, recordings, out, names, max_effects, seed, figures=not no_figures, progress=progress,
                          n_jobs=jobs, total=total)
    typer.echo(f"verdict: {finder.verdict_}")
    typer.echo(finder.explanation_)
    typer.echo(f"wrote {out / 'gap.json'}")


@app.command("bench")
def bench_cmd(
    cases: int = typer.Option(22, "--cases", help="number of concealed-effect cases"),
    noise: float = typer.Option(0.001, "--noise", help="position noise in m"),
    seed: int = typer.Option(0, "--seed"),
    jobs: int = typer.Option(1, "--jobs", help="worker processes"),
) -> None:
    """Benchmark identification on recordings with a concealed random effect (or none)."""
    from voe.gap.bench import run_bench
    from voe.gap.bench_score import summary_lines

    def show(r: dict) -> None:
        typer.echo(f"  case {r['seed']}: true {r['truth']:<22} named {','.join(r['names']) or '-':<22} "
                   f"rmse {r['before']:.4g} -> {r['after']:.4g}")

    results = run_bench(cases, noise, seed, jobs, progress=show)
    for line in summary_lines(results, noise):
        typer.echo(line)
