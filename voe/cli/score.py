"""``voe score``: run a model over a probe set (or read outside surprises) and store a run."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output


def _forward(probes: Path, model: str | None, out: Path, checkpoint: Path | None, model_arg: list[str] | None,
             batch_size: int, seed: int, no_check: bool, cache: Path | None, device: str | None,
             bf16: bool, overwrite: bool) -> list[str]:
    """The same ``voe score`` arguments for each torchrun rank (launcher options dropped)."""
    argv = ["score", "--probes", str(probes), "--out", str(out), "--batch-size", str(batch_size),
            "--seed", str(seed)]
    argv += ["--model", model] if model else []
    argv += ["--checkpoint", str(checkpoint)] if checkpoint else []
    for kv in model_arg or []:
        argv += ["--model-arg", kv]
    argv += ["--cache", str(cache)] if cache else []
    argv += ["--device", device] if device else []
    argv += [flag for flag, on in (("--no-check", no_check), ("--bf16", bf16), ("--overwrite", overwrite)) if on]
    return argv


class _Bar:
    """A progress bar opened at the first finished batch, so a failed pre-run check prints one line."""

    def __init__(self, total: int, desc: str) -> None:
        self.total, self.desc, self.bar = total, desc, None

    def __call__(self, n: int) -> None:
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=self.total, desc=self.desc, unit="clip", dynamic_ncols=True)
        self.bar.update(n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def register(app: typer.Typer) -> None:
    """Add the top-level ``score`` command to ``app``."""

    @app.command("score")
    @claims_output("dir")
    def score(
        probes: Path = typer.Option(..., "--probes", help="Probe-set directory."),
        out: Path = typer.Option(..., "--out", help="Run directory to write (must be new or empty)."),
        model: str = typer.Option(None, "--model", help="Registered model id or 'module:attr'."),
        checkpoint: Path | None = typer.Option(None, "--checkpoint", help="Weights to load."),
        model_arg: list[str] = typer.Option(None, "--model-arg", help="Model argument k=v (repeatable)."),
        batch_size: int = typer.Option(16, "--batch-size", min=1, help="At most this many clips per frame_nll call."),
        seed: int = typer.Option(0, "--seed", help="Seed of the clip order and the common random numbers."),
        no_check: bool = typer.Option(False, "--no-check", help="Skip check_model on a sample before the run."),
        cache: Path | None = typer.Option(None, "--cache", help="Resumable cache root [default: $XDG_CACHE_HOME/voe/score]."),
        no_cache: bool = typer.Option(False, "--no-cache", help="Keep nothing for resumption (single process only)."),
        device: str | None = typer.Option(None, "--device", help="torch device for models with to(device), e.g. cuda."),
        bf16: bool = typer.Option(False, "--bf16", help="bf16 autocast around each frame_nll call (torch models)."),
        launcher: str = typer.Option("python", "--launcher", help="python (this process) or torchrun."),
        nproc: int = typer.Option(2, "--nproc", min=1, help="Ranks for --launcher torchrun."),
        surprises: Path | None = typer.Option(None, "--surprises", help="Score a table computed elsewhere: csv/parquet with clip_key, [frame,] surprise."),
        surprise_kind: str = typer.Option("nll", "--surprise-kind", help="With --surprises: nll, bound or error."),
        name: str | None = typer.Option(None, "--name", help="With --surprises: the model name in reports [default: file stem]."),
        overwrite: bool = typer.Option(False, help="Replace an existing run directory."),
    ) -> None:
        """Score every clip blind (opaque keys, shuffled order) and write frames.parquet, clips.parquet, run.json."""
        from voe.errors import VoeError

        if launcher not in ("python", "torchrun"):
            raise VoeError(f"--launcher must be python or torchrun, not {launcher!r}")
        if surprises is not None:
            if model is not None or launcher != "python":
                raise VoeError("--surprises scores a table computed elsewhere; drop --model and --launcher")
            from voe.scoring.external import score_surprises

            meta = score_surprises(probes, surprises, out, kind=surprise_kind, name=name, overwrite=overwrite)
            typer.echo(f"wrote {meta['probes']['n_clips']} clips of {surprises.name} "
                       f"(surprise kind {meta['surprise_kind']}) to {out}")
            return
        if model is None:
            raise VoeError("give --model (a registered id or module:attr) or --surprises FILE")
        if launcher == "torchrun":
            import os

            from voe.scoring.distributed import torchrun_argv

            argv = torchrun_argv(nproc, _forward(probes, model, out, checkpoint, model_arg, batch_size, seed,
                                                 no_check, cache, device, bf16, overwrite))
            typer.echo(" ".join(argv), err=True)
            os.execv(argv[0], argv)

        from voe.cli.common import parse_kv
        from voe.io.probeset import load_probe_set
        from voe.models.loading import load_model
        from voe.scoring.cache import default_root
        from voe.scoring.distributed import from_env
        from voe.scoring.score import score_probe_set

        ranks = from_env()
        if no_cache and ranks.world > 1:
            raise VoeError("--no-cache cannot be used with torchrun: ranks hand their results over in the cache")
        root = None if no_cache else (cache or default_root())
        bar = None
        try:
            ps = load_probe_set(probes)
            args = parse_kv(model_arg)
            m = load_model(model, args, checkpoint)
            desc = f"scoring {getattr(m, 'name', model)}" + (f" [rank {ranks.rank}/{ranks.world}]" if ranks.world > 1 else "")
            bar = _Bar(len(ps) // ranks.world, desc)
            meta = score_probe_set(m, ps, out, model_ref=model, model_args=args, checkpoint=checkpoint,
                                   batch_size=batch_size, seed=seed, check=not no_check, cache_root=root,
                                   device=device, bf16=bf16, overwrite=overwrite, ranks=ranks, progress=bar)
        finally:
            if bar is not None:
                bar.close()
            ranks.close()
        if meta is not None:
            typer.echo(f"wrote {meta['probes']['n_clips']} clips scored by {meta['model']['name']} to {out} "
                       f"({meta['wall_time_s']:.1f} s, check {meta['check']}, "
                       f"{meta['clips_from_cache']} from cache)")
