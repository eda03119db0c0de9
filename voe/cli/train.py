"""``voe train``: train a learned model (or calibrate a reference) and write a checkpoint."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output


@claims_output("dir")
def train(
    model: str = typer.Argument(..., help="Registered model name (see `voe model list`)."),
    data: Path = typer.Option(..., "--data", help="Training set from `voe world generate`."),
    out: Path = typer.Option(..., "--out", help="Checkpoint directory to write."),
    steps: int = typer.Option(None, "--steps", min=1, help="Optimiser steps (default: the model's preset); "
                                                            "the learning-rate schedule follows the steps."),
    minutes: float = typer.Option(None, "--minutes", min=0.01, help="Safety cap on wall time; a capped run "
                                                                     "is recorded as such and depends on the machine."),
    device: str = typer.Option("cpu", "--device", help="cpu or cuda."),
    seed: int = typer.Option(0, "--seed", help="Seed of initialisation, split and batches."),
    val_frac: float = typer.Option(0.1, "--val-frac", min=0.0, max=0.9, help="Held-out fraction."),
    model_arg: list[str] = typer.Option(None, "--model-arg", help="key=value (repeatable)."),
    overwrite: bool = typer.Option(False, help="Replace an existing checkpoint directory."),
) -> None:
    """Train MODEL on a training set; shows progress and validation NLL (nats per frame)."""
    from voe.cli.common import parse_kv
    from voe.errors import VoeError
    from voe.models.train import TrainConfig
    from voe.models.train import train as run

    if device not in ("cpu", "cuda"):
        raise VoeError(f"--device must be cpu or cuda, got '{device}'")
    from voe.io.probeset import load_probe_set
    from voe.models import MODELS

    MODELS.resolve(model)  # an unknown name fails (with did-you-mean) before the data is read
    load_probe_set(data)  # a missing or malformed training set fails before any work
    cfg = TrainConfig(steps=steps, minutes=minutes, device=device, seed=seed, val_frac=val_frac)
    from tqdm import tqdm

    state: dict = {"val": float("nan"), "bar": None}

    def report(step: int, loss: float, val: float | None) -> None:
        if state["bar"] is None:  # created once the data has loaded, so errors stay one line
            state["bar"] = tqdm(total=steps, desc=f"train {model}", unit="step", dynamic_ncols=True)
        bar = state["bar"]
        if val is not None:
            state["val"] = val
        bar.update(1)
        bar.set_postfix(loss=f"{loss:.2f}", val_nll=f"{state['val']:.2f}", refresh=False)

    try:
        meta = run(model, data, out, cfg, parse_kv(model_arg), report)
    finally:
        if state["bar"] is not None:
            state["bar"].close()
    typer.echo(f"wrote {out}: {meta['model']}, {meta['steps']} steps in {meta['seconds']:.0f} s, "
               f"validation NLL {meta['val_nll']:.3f} nats/frame")


def register(app: typer.Typer) -> None:
    """Add the top-level ``train`` command."""
    app.command("train")(train)
