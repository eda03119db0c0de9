"""``voe demo``: the main job, from probes through training and scoring to a report."""

from __future__ import annotations

from pathlib import Path

import typer


def register(app: typer.Typer) -> None:
    @app.command()
    def demo(
        out: Path = typer.Option(Path("reports/demo"), "--out", help="Report directory."),
        work: Path = typer.Option(Path("voe-work/demo"), "--work",
                                  help="Where probes, worlds, checkpoints and runs go (reused on rerun)."),
        quick: bool = typer.Option(False, "--quick", help="A tiny, fast version (smoke test; numbers "
                                                          "are not meaningful)."),
        validity: bool = typer.Option(True, "--validity/--no-validity",
                                      help="Also run the validity controls (the report's 'Is the suite valid?')."),
        seed: int = typer.Option(0, help="Seed of probes, worlds and training."),
    ) -> None:
        """Generate probes and training worlds, train the built-in models, score every model and
        write the comparison report (about 15 minutes on 2 CPU cores)."""
        from voe.demo import DemoConfig, run_demo

        if quick:
            cfg = DemoConfig(per_concept=4, world_n=60, cf_world_n=40, calib_n=30, size=32, seed=seed, validity=validity,
                             minutes={"interaction": 0.1, "pixel": 0.1, "mlp": 0.1,
                                      "cf-gravity_off": 0.1, "cf-pass_through": 0.1})
        else:
            cfg = DemoConfig(seed=seed, validity=validity)
        times = run_demo(out, work, cfg, say=typer.echo)
        typer.echo("stage times (s): " + ", ".join(f"{k} {v:.0f}" for k, v in times.items()))
        typer.echo(f"report: {out / 'report.md'} and {out / 'report.html'}")
