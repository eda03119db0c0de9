"""``voe validate-suite``: the validity controls and their specificity matrix."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output


def register(app: typer.Typer) -> None:
    @app.command("validate-suite")
    @claims_output("dir", replaces=("matrix.csv",))
    def validate_suite(
        out: Path = typer.Option(Path("reports/validity"), "--out", help="Report directory."),
        probes: Path = typer.Option(None, "--probes", help="Probe set (default: generate the core suite)."),
        world: Path = typer.Option(None, "--world", help="Training set for calibration (default: generate)."),
        work: Path = typer.Option(None, "--work", help="Scratch directory, reused on rerun (default: "
                                                      "$XDG_CACHE_HOME/voe/validity-..., printed)."),
        controls: Path = typer.Option(None, "--controls", help="YAML file of your own controls."),
        family: list[str] = typer.Option(None, "--family",
                                         help="Only these built-in families: knowledge-free, random-net, "
                                              "physics-poor, lesion, counterfactual (repeatable)."),
        per_concept: int = typer.Option(None, "--per-concept", min=2,
                                        help="Sets per concept if generating (default: enough for a "
                                             "perfect score per condition to be decisive, 18 for 8 concepts)."),
        world_n: int = typer.Option(600, "--world-n", min=10, help="Training clips if generating."),
        train_steps: int = typer.Option(None, "--train-steps", min=1,
                                        help="Optimiser steps per counterfactual model (default: its preset)."),
        seed: int = typer.Option(0),
        jobs: int = typer.Option(1, "--jobs", min=1, help="Controls built and scored at a time."),
        overwrite: bool = typer.Option(False, help="Replace a non-empty --out that is not an earlier validity report."),
        show_paths: bool = typer.Option(False, "--show-paths", help="Record absolute input paths in provenance."),
    ) -> None:
        """Run knowledge-free, random, physics-poor, lesioned and counterfactual controls; write the matrix."""
        from voe.controls.builtin import FAMILIES
        from voe.controls.spec import load_user_controls
        from voe.controls.suite import validate_suite as run
        from voe.errors import VoeError

        bad = [f for f in family or [] if f not in FAMILIES]
        if bad:
            raise VoeError(f"unknown control family {bad[0]!r} (known: {', '.join(FAMILIES)})")
        from voe.io.lock import output_lock
        from voe.io.outputs import scratch_dir
        from voe.io.probeset import load_probe_set

        user = load_user_controls(controls) if controls else []
        for given in (probes, world):  # inputs are checked before any work
            if given is not None:
                load_probe_set(given)
        fams = tuple(family) if family else (() if user and family is not None else None)
        if per_concept is None and probes is None:
            from voe.concepts import SUITES
            from voe.controls.suite import default_per_concept

            per_concept = default_per_concept(len(SUITES["core"]))
        sizes = f"{per_concept}x{world_n}" if probes is None else f"given-x{world_n}"
        work = work or scratch_dir(f"validity-{sizes}-seed{seed}")
        typer.echo(f"scratch directory (reused on rerun): {work}")
        with output_lock(work):
            matrix = run(out, work, probes, world, user, fams or None, per_concept, world_n, seed,
                         train_steps=train_steps, say=typer.echo, jobs=jobs, show_paths=show_paths)
        live = matrix[matrix["could_fail"].eq(True)]
        fixed = matrix[matrix["could_fail"].eq(False)]
        typer.echo(f"wrote {out}/validity.md: cells that could have failed: {int(live['as_declared'].eq(True).sum())} "
                   f"as declared, {int(live['as_declared'].eq(False).sum())} not; cells that could not fail "
                   f"(by construction): {int(fixed['as_declared'].eq(True).sum())} as declared, "
                   f"{int(fixed['as_declared'].eq(False).sum())} not")
