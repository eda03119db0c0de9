"""``voe world``: generate training worlds (ordinary or counterfactual physics)."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output

app = typer.Typer(help="Generate training worlds.", no_args_is_help=True)


@app.command()
@claims_output("dir")
def generate(
    out: Path = typer.Option(..., "--out", help="Directory to write (must be new or empty)."),
    n: int = typer.Option(..., "--n", min=1, help="Number of clips."),
    seed: int = typer.Option(0, help="Master seed; the same seed gives byte-identical sets."),
    size: int = typer.Option(64, min=16, max=512, help="Frame side in pixels."),
    n_frames: int = typer.Option(40, "--frames", min=10, help="Frames per clip."),
    counterfactual: str = typer.Option("none", help="none, gravity_off, pass_through or vanish_when_occluded."),
    jobs: int = typer.Option(1, min=1, help="Worker processes."),
    overwrite: bool = typer.Option(False, help="Replace an existing output directory."),
) -> None:
    """Generate an ordinary-physics (or counterfactual) training set with role ``train``."""
    from voe.cli.common import progress
    from voe.sim.scene import SimConfig
    from voe.world.generate import check_counterfactual, generate_world

    check_counterfactual(counterfactual)
    cfg = SimConfig(size=size, n_frames=n_frames)
    with progress(n, "training clips", "clip") as tick:
        m = generate_world(out, n, seed, cfg, counterfactual, jobs, overwrite, tick)
    typer.echo(f"wrote {m['n_clips']} training clips ({counterfactual}) to {out}")
