"""``voe score``: run a model over a probe set (or read outside surprises) and store a run."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import typer


@dataclass(frozen=True)
class _Opts:
    """The options of one ``voe score`` call, passed on explicitly."""

    probes: Path
    out: Path
    model: str | None
    checkpoint: Path | None
    model_arg: tuple[str, ...]
    batch_size: int
    seed: int
    no_check: bool
    cache: Path | None
    no_cache: bool
    device: str | None
    bf16: bool
    launcher: str
    nproc: int
    shard: str | None
    surprises: Path | None
    surprise_kind: str
    name: str | None
    overwrite: bool

    def rank_argv(self) -> list[str]:
        """The same ``voe score`` arguments for each torchrun rank (launcher options dropped)."""
        argv = ["score", "--probes", str(self.probes), "--out", str(self.out), "--batch-size",
                str(self.batch_size), "--seed", str(self.seed), "--model", str(self.model)]
        argv += ["--checkpoint", str(self.checkpoint)] if self.checkpoint else []
        for kv in self.model_arg:
            argv += ["--model-arg", kv]
        argv += ["--cache", str(self.cache)] if self.cache else []
        argv += ["--device", self.device] if self.device else []
        return argv + [flag for flag, on in (("--no-check", self.no_check), ("--bf16", self.bf16),
                                             ("--overwrite", self.overwrite)) if on]


class _Bar:
    """Progress, started at the first finished batch (so a failed pre-run check prints one line):
    a line naming the cache directory, then a bar if stderr is a terminal (logs of torchrun ranks
    and SLURM tasks stay readable)."""

    def __init__(self, total: int, desc: str, note: str) -> None:
        self.total, self.desc, self.note, self.bar = total, desc, note, None

    def __call__(self, n: int) -> None:
        if self.bar is None:
            from tqdm import tqdm

            typer.echo(f"{self.desc}: {self.total} clips, {self.note}", err=True)
            self.bar = tqdm(total=self.total, desc=self.desc, unit="clip", dynamic_ncols=True, disable=None)
        self.bar.update(n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _shard(text: str):
    """``I/N`` -> the ranks of one job-array task (0-based I)."""
    from voe.parallel import parse_shard
    from voe.scoring.distributed import Ranks

    i, n = parse_shard(text)
    return Ranks(i, n, "shard")


def _external(o: _Opts) -> None:
    from voe.errors import VoeError
    from voe.scoring.external import score_surprises

    if o.model is not None or o.launcher != "python" or o.shard:
        raise VoeError("--surprises scores a table computed elsewhere; drop --model, --launcher and --shard")
    meta = score_surprises(o.probes, o.surprises, o.out, kind=o.surprise_kind, name=o.name, overwrite=o.overwrite)
    typer.echo(f"wrote {meta['probes']['n_clips']} clips of {o.surprises.name} "
               f"(surprise kind {meta['surprise_kind']}) to {o.out}")


def _torchrun(o: _Opts) -> None:
    from voe.scoring.distributed import torchrun_argv

    argv = torchrun_argv(o.nproc, o.rank_argv())
    typer.echo(" ".join(argv), err=True)
    os.execv(argv[0], argv)


def _in_process(o: _Opts) -> None:
    from voe.cli.common import parse_kv
    from voe.errors import VoeError
    from voe.io.probeset import load_probe_set
    from voe.models.loading import load_model
    from voe.scoring.cache import default_root
    from voe.scoring.distributed import from_env
    from voe.scoring.score import score_probe_set

    ranks = _shard(o.shard) if o.shard else from_env()
    bar = None
    try:
        if o.no_cache and ranks.world > 1:
            raise VoeError("--no-cache cannot be used with torchrun or --shard: results are handed over in the cache")
        root = None if o.no_cache else (o.cache or default_root())
        ps = load_probe_set(o.probes)
        args = parse_kv(list(o.model_arg))
        m = load_model(o.model, args, o.checkpoint)
        rank = f" [rank {ranks.rank}/{ranks.world}]" if ranks.world > 1 else ""
        note = f"check {'skipped' if o.no_check else 'passed'}, " + (f"cache under {root}" if root else "no cache")
        bar = _Bar(len(ps) // ranks.world, f"scoring {getattr(m, 'name', o.model)}{rank}", note)
        meta = score_probe_set(m, ps, o.out, model_ref=o.model, model_args=args, checkpoint=o.checkpoint,
                               batch_size=o.batch_size, seed=o.seed, check=not o.no_check, cache_root=root,
                               device=o.device, bf16=o.bf16, overwrite=o.overwrite, ranks=ranks, progress=bar)
    finally:
        if bar is not None:
            bar.close()
        ranks.close()
    if o.shard:
        typer.echo(f"scored shard {o.shard} into the cache under {root}; run again without --shard to write {o.out}")
    elif meta is not None:
        typer.echo(f"wrote {meta['probes']['n_clips']} clips scored by {meta['model']['name']} to {o.out} "
                   f"({meta['wall_time_s']:.1f} s, check {meta['check']}, {meta['clips_from_cache']} from cache)")


def register(app: typer.Typer) -> None:
    """Add the top-level ``score`` command to ``app``."""

    @app.command("score")
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
        shard: str | None = typer.Option(None, "--shard", help="I/N: fill the cache with shard I of N only (a SLURM array task); a final run without --shard writes the run."),
        surprises: Path | None = typer.Option(None, "--surprises", help="Score a table computed elsewhere: csv/parquet with clip_key, [frame,] surprise."),
        surprise_kind: str = typer.Option("nll", "--surprise-kind", help="With --surprises: nll, bound or error."),
        name: str | None = typer.Option(None, "--name", help="With --surprises: the model name in reports [default: file stem]."),
        overwrite: bool = typer.Option(False, help="Replace an existing run directory."),
    ) -> None:
        """Score every clip blind (opaque keys, shuffled order) and write frames.parquet, clips.parquet, run.json."""
        import contextlib

        from voe.errors import VoeError
        from voe.io.outputs import check_output, claim_output

        o = _Opts(probes, out, model, checkpoint, tuple(model_arg or ()), batch_size, seed, no_check, cache,
                  no_cache, device, bf16, launcher, nproc, shard, surprises, surprise_kind, name, overwrite)
        if launcher not in ("python", "torchrun"):
            raise VoeError(f"--launcher must be python or torchrun, not {launcher!r}")
        if surprises is None and model is None:
            raise VoeError("give --model (a registered id or module:attr) or --surprises FILE")
        if surprises is None and (surprise_kind != "nll" or name):
            raise VoeError("--surprise-kind and --name go with --surprises; a model declares its own "
                           "surprise_kind and name")
        # The output is checked before any work. Its lock is held by the process that writes the
        # run: not a launcher that execs torchrun (its pid lives on as torchrun's), not a job-array
        # shard, not a rank other than 0.
        check_output(out, "dir", overwrite)
        writes = launcher == "python" and not shard and int(os.environ.get("RANK", "0") or 0) == 0
        with claim_output(out, "dir", overwrite) if writes else contextlib.nullcontext():
            if surprises is not None:
                _external(o)
            elif launcher == "torchrun":
                _torchrun(o)
            else:
                _in_process(o)
