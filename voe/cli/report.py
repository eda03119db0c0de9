"""``voe report``: compare stored runs in a markdown/html report with figures and summary.csv."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output


def register(app: typer.Typer) -> None:
    """Add the top-level ``report`` command to ``app``."""

    @app.command("report")
    @claims_output("dir")
    def report(
        runs: list[Path] = typer.Argument(..., help="Run directories written by `voe score`."),
        out: Path = typer.Option(..., "--out", help="Report directory, e.g. reports/NAME."),
        title: str | None = typer.Option(None, help="Report title."),
        seed: int = typer.Option(0, help="Seed of the bootstrap and permutation tests."),
        overwrite: bool = typer.Option(False, help="Replace an existing report directory."),
        show_paths: bool = typer.Option(False, "--show-paths",
                                        help="Name the probe set by its absolute path (default: folder name "
                                             "and manifest sha256)."),
    ) -> None:
        """Build report.md, report.html, summary.csv and figures from stored runs (no model is run)."""
        from voe.report.build import build_report

        summary = build_report(runs, out, title=title, seed=seed, overwrite=overwrite, show_paths=show_paths)
        counts = summary["verdict"].value_counts().to_dict()
        typer.echo(f"wrote {out / 'report.html'}: {len(summary)} model x concept cells "
                   f"({', '.join(f'{v} {k}' for k, v in sorted(counts.items()))})")
