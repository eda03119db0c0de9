"""``voe model``: list the built-in models and check any model against the protocol."""

from __future__ import annotations

from pathlib import Path

import typer

app = typer.Typer(help="List built-in models and check models against the protocol.", no_args_is_help=True)


@app.command("list")
def list_models() -> None:
    """List registered models (name, observation, learned or reference, summary)."""
    from voe.models import MODELS

    for mid in MODELS.ids():
        meta = MODELS.meta(mid)
        kind = "learned" if meta.get("learned") else "reference"
        typer.echo(f"{mid:<16} {meta.get('observation', '?'):<7} {kind:<10} {meta.get('summary', '')}")


@app.command()
def check(
    ref: str = typer.Argument(..., help="Registered name or package.module:attr."),
    model_arg: list[str] = typer.Option(None, "--model-arg", help="key=value (repeatable)."),
    checkpoint: Path = typer.Option(None, "--checkpoint", help="Checkpoint directory from `voe train`."),
    data: Path = typer.Option(None, "--data", help="Probe or training set to check on (default: 6 fresh training clips)."),
    n: int = typer.Option(6, "--n", min=2, help="Clips to check on."),
) -> None:
    """Check the frame_nll contract: shape and values, determinism, invariance to clip order, to
    clip keys and to batch size, and causality. A failure is one line naming the check (exit 2)."""
    from voe.cli.common import parse_kv
    from voe.models.check import check_model
    from voe.models.loading import load_model

    model = load_model(ref, parse_kv(model_arg), checkpoint)
    batch = _check_batch(data, n)
    check_model(model, batch)
    typer.echo(f"{ref}: ok ({model.name}, observation={model.observation}, {batch.shape[0]} clips x "
               f"{batch.shape[1]} frames)")


def _check_batch(data: Path | None, n: int):
    from voe.io.probeset import load_probe_set

    if data is None:
        import tempfile

        from voe.sim.scene import SimConfig
        from voe.world.generate import generate_world

        tmp = Path(tempfile.mkdtemp(prefix="voe-check-")) / "world"
        generate_world(tmp, n, 12345, SimConfig())
        data = tmp
    from voe.scoring.order import Blinder, plan

    ps = load_probe_set(data)
    blinder = Blinder(ps)
    return blinder.batch(blinder.sample(plan(ps.index, n), n))  # what the harness shows: opaque keys, shuffled
