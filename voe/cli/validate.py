"""``voe validate-suite``: the validity controls and their specificity matrix."""

from __future__ import annotations

from pathlib import Path

import typer


def register(app: typer.Typer) -> None:
    @app.command("validate-suite")
    def validate_suite(
        out: Path = typer.Option(Path("reports/validity"), "--out", help="Report directory."),
        probes: Path = typer.Option(None, "--probes", help="Probe set (default: generate the core suite)."),
        world: Path = typer.Option(None, "--world", help="Training set for calibration (default: generate)."),
        work: Path = typer.Option(Path("voe-work/validity"), "--work", help="Scratch directory (reused)."),
        controls: Path = typer.Option(None, "--controls", help="YAML file of your own controls."),
        family: list[str] = typer.Option(None, "--family",
                                         help="Only these built-in families: knowledge-free, random-net, "
                                              "physics-poor, lesion, counterfactual (repeatable)."),
        per_concept: int = typer.Option(None, "--per-concept", min=2,
                                        help="Sets per concept if generating (default: enough for a "
                                             "perfect score per condition to be decisive, 18 for 8 concepts)."),
        world_n: int = typer.Option(600, "--world-n", min=10, help="Training clips if generating."),
        train_minutes: float = typer.Option(3.0, "--train-minutes", help="Per counterfactual model."),
        seed: int = typer.Option(0),
        jobs: int = typer.Option(1, "--jobs", min=1, help="Controls built and scored at a time."),
    ) -> None:
        """Run knowledge-free, random, physics-poor, lesioned and counterfactual controls; write the matrix."""
        from voe.controls.builtin import FAMILIES
        from voe.controls.spec import load_user_controls
        from voe.controls.suite import validate_suite as run
        from voe.errors import VoeError

        bad = [f for f in family or [] if f not in FAMILIES]
        if bad:
            raise VoeError(f"unknown control family {bad[0]!r} (known: {', '.join(FAMILIES)})")
        user = load_user_controls(controls) if controls else []
        fams = tuple(family) if family else (() if user and family is not None else None)
        matrix = run(out, work, probes, world, user, fams or None, per_concept, world_n, seed,
                     train_minutes=train_minutes, say=typer.echo, jobs=jobs)
        live = matrix[matrix["could_fail"].eq(True)]
        fixed = matrix[matrix["could_fail"].eq(False)]
        typer.echo(f"wrote {out}/validity.md: cells that could have failed: {int(live['as_declared'].eq(True).sum())} "
                   f"as declared, {int(live['as_declared'].eq(False).sum())} not; cells that could not fail "
                   f"(by construction): {int(fixed['as_declared'].eq(True).sum())} as declared, "
                   f"{int(fixed['as_declared'].eq(False).sum())} not")
