"""``voe demo``: the main job, from probes through training and scoring to a report."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output


def register(app: typer.Typer) -> None:
    @app.command()
    @claims_output("dir", replaces=("report.md",))
    def demo(
        out: Path = typer.Option(Path("reports/demo"), "--out", help="Report directory."),
        work: Path = typer.Option(None, "--work",
                                  help="Where probes, worlds, checkpoints and runs go, reused on rerun "
                                       "(default: $XDG_CACHE_HOME/voe/demo-..., printed)."),
        quick: bool = typer.Option(False, "--quick", help="A tiny, fast version (smoke test; numbers "
                                                          "are not meaningful)."),
        validity: bool = typer.Option(True, "--validity/--no-validity",
                                      help="Also run the validity controls (the report's 'Is the suite valid?')."),
        seed: int = typer.Option(0, help="Seed of probes, worlds and training."),
    ) -> None:
        """Generate probes and training worlds, train the built-in models, score every model and
        write the comparison report (about 15 minutes on 2 CPU cores)."""
        from voe.demo import DemoConfig, run_demo
        from voe.io.lock import output_lock
        from voe.io.outputs import scratch_dir

        if quick:
            cfg = DemoConfig(per_concept=4, world_n=60, cf_world_n=40, calib_n=30, size=32, seed=seed, validity=validity,
                             steps={"interaction": 10, "pixel": 10, "mlp": 20,
                                    "cf-gravity_off": 10, "cf-pass_through": 10})
        else:
            cfg = DemoConfig(seed=seed, validity=validity)
        work = work or scratch_dir(f"demo{'-quick' if quick else ''}-seed{seed}")
        typer.echo(f"scratch directory (reused on rerun): {work}")
        with output_lock(work):
            times = run_demo(out, work, cfg, say=typer.echo)
        typer.echo("stage times (s): " + ", ".join(f"{k} {v:.0f}" for k, v in times.items()))
        typer.echo(f"report: {out / 'report.md'} and {out / 'report.html'}")
