"""``voe score``: run a model over a probe set and store its per-frame surprise."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output


def register(app: typer.Typer) -> None:
    """Add the top-level ``score`` command to ``app``."""

    @app.command("score")
    @claims_output("dir")
    def score(
        probes: Path = typer.Option(..., "--probes", help="Probe-set directory."),
        model: str = typer.Option(..., "--model", help="Registered model id or 'module:attr'."),
        out: Path = typer.Option(..., "--out", help="Run directory to write (must be new or empty)."),
        checkpoint: Path | None = typer.Option(None, "--checkpoint", help="Weights to load."),
        model_arg: list[str] = typer.Option(None, "--model-arg", help="Model argument k=v (repeatable)."),
        batch_size: int = typer.Option(16, "--batch-size", min=1, help="Clips per frame_nll call."),
        overwrite: bool = typer.Option(False, help="Replace an existing run directory."),
    ) -> None:
        """Score every clip (teacher-forced) and write frames.parquet, clips.parquet, run.json."""
        from voe.cli.common import parse_kv, progress
        from voe.io.probeset import load_probe_set
        from voe.models.loading import load_model
        from voe.scoring.score import score_probe_set

        ps = load_probe_set(probes)
        args = parse_kv(model_arg)
        m = load_model(model, args, checkpoint)
        with progress(len(ps), f"scoring {getattr(m, 'name', model)}", "clip") as tick:
            meta = score_probe_set(m, ps, out, model_ref=model, model_args=args, checkpoint=checkpoint,
                                   batch_size=batch_size, overwrite=overwrite, progress=tick)
        typer.echo(f"wrote {meta['probes']['n_clips']} clips scored by {meta['model']['name']} to {out} "
                   f"({meta['wall_time_s']:.1f} s)")
