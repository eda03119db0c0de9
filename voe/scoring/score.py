"""Score a model on every clip of a probe set (teacher-forced), blind, and store the run on disk.

Why teacher forcing only: ``frame_nll`` is given the stored clip and returns its per-frame
surprise, so there is nothing to roll out; every metric is then a function of these numbers alone.

Why blind: the model sees frames, states, presence, feature names, dt, geometry, opaque clip keys
and common-random-number seeds, in a seeded shuffled order with at most one clip of a matched set
per batch (``voe.scoring.order``). Results are stored by clip id as always (``voe.scoring.store``).
Batches are cached as they are computed (``voe.scoring.cache``) so a run can resume, and ranks of
a ``torchrun`` launch each score their own groups of matched sets (``voe.scoring.distributed``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from voe import __version__
from voe.errors import ModelContractError, RunError, VoeError
from voe.io.paths import portable_ref
from voe.io.probeset import ProbeSet, load_probe_set
from voe.io.provenance import sha256_path
from voe.scoring.cache import ScoreCache, code_sha256
from voe.scoring.device import place, precision
from voe.scoring.distributed import SINGLE, Ranks, rank_device
from voe.scoring.order import CRN_RULE, Blinder, Schedule, plan
from voe.scoring.store import assemble, check_nll, surprise_kind, write_run

#: Clips (from different matched sets) that ``check_model`` is run on before a checked run.
CHECK_CLIPS = 6


def check_sample(model: Any, blinder: Blinder, sched: Schedule, n: int = CHECK_CLIPS) -> None:
    """Run ``check_model`` on the first ``n`` clips of the schedule from distinct matched sets."""
    from voe.models.check import check_model

    ids = blinder.sample(sched, n)
    if len(ids) >= 2:
        check_model(model, blinder.batch(ids))


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text[:300] + ("..." if len(text) > 300 else "")


def _call(model: Any, name: str, batch, blinder: Blinder, done: int, cache: ScoreCache | None) -> Any:
    """``model.frame_nll(batch)``; a model that raises becomes one line naming it and the clip."""
    try:
        return model.frame_nll(batch)
    except VoeError:
        raise
    except Exception as exc:
        more = f" (and {len(batch) - 1} more in its batch)" if len(batch) > 1 else ""
        kept = (f"{done} clips scored before it are kept in {cache.dir}; rerun the same command to resume"
                if cache is not None else "rerun with a cache (voe score, or cache=...) to keep partial results")
        raise ModelContractError(f"model '{name}' raised {type(exc).__name__} on clip "
                                 f"{blinder.describe(batch.clip_ids[0])}{more}: {_one_line(exc)}; "
                                 f"{kept}") from exc


def score_batches(model: Any, blinder: Blinder, sched: Schedule, todo: Sequence[int], *,
                  cache: ScoreCache | None = None, device: str | None = None, bf16: bool = False,
                  progress: Callable[[int], None] | None = None) -> tuple[dict[str, np.ndarray], int]:
    """Surprise ``(T,)`` per clip id of batches ``todo``, and how many clips were computed (not cached)."""
    name = str(getattr(model, "name", type(model).__name__))
    out: dict[str, np.ndarray] = {}
    computed = 0
    for i in todo:
        ids = sched.batches[i]
        keys = tuple(blinder.key[c] for c in ids)
        nll = cache.get(i, keys) if cache is not None else None
        if nll is None:
            batch = blinder.batch(ids)
            with precision(device, bf16):
                raw = _call(model, name, batch, blinder, len(out), cache)
            nll = check_nll(raw, batch.shape, name, tuple(blinder.describe(k) for k in keys))
            if cache is not None:
                cache.put(i, keys, nll)
            computed += len(ids)
        out.update(zip(ids, nll, strict=True))
        if progress:
            progress(len(ids))
    return out, computed


def _merge(sched: Schedule, blinder: Blinder, cache: ScoreCache) -> dict[str, np.ndarray]:
    """Rank 0: every batch of every rank, read back from the shared cache by clip key."""
    out: dict[str, np.ndarray] = {}
    for i, ids in enumerate(sched.batches):
        nll = cache.get(i, tuple(blinder.key[c] for c in ids))
        if nll is None:
            raise RunError(f"batch {i} of the schedule is missing from {cache.dir} after every rank "
                           "finished; is the cache directory shared by all ranks (--cache on shared storage)?")
        out.update(zip(ids, nll, strict=True))
    return out


def _training(checkpoint: Path | None) -> dict[str, Any] | None:
    """The checkpoint's training record (steps, time cap, validation NLL), for the report to show."""
    if checkpoint is None:  # a user's model scored without a checkpoint: nothing to import or record
        return None
    from voe.models.checkpoint import training_record

    return training_record(Path(checkpoint))


def score_probe_set(model: Any, probes: ProbeSet | str | Path, out: Path, *, model_ref: str | None = None,
                    model_args: dict[str, Any] | None = None, checkpoint: Path | None = None,
                    batch_size: int = 16, seed: int = 0, check: bool = False,
                    cache_root: Path | None = None, device: str | None = None, bf16: bool = False,
                    overwrite: bool = False, ranks: Ranks = SINGLE,
                    progress: Callable[[int], None] | None = None) -> dict[str, Any] | None:
    """Run ``model.frame_nll`` over every clip of ``probes`` and write a run directory to ``out``.

    Args:
        model: anything following ``voe.models.protocol.Model``.
        probes: a probe set or its directory.
        out: the run directory, written atomically (must be new or empty unless ``overwrite``).
        model_ref, model_args, checkpoint: how the model was made, recorded in ``run.json``.
        batch_size: at most this many clips per ``frame_nll`` call.
        seed: seeds the clip order and the common random numbers (``batch.seeds``).
        check: run ``check_model`` on a small sample first (``voe score`` does unless --no-check).
        cache_root: keep computed batches under this directory and resume from them; the entry
            is removed once the run is written. ``None``: no cache (unless sharded).
        device, bf16: see ``voe.scoring.device``.
        ranks: this process's place in a sharded launch (``voe.scoring.distributed.from_env``, or
            ``Ranks(i, n, "shard")`` for one task of a job array: it only fills the cache, and a
            final unsharded run with the same cache merges every task's batches).
        progress: called with the number of clips done after each batch.

    Returns:
        The ``run.json`` contents (``None`` on ranks other than 0, which write nothing).
    """
    out = Path(out)
    if out.exists() and (not out.is_dir() or any(out.iterdir())) and not overwrite:
        raise VoeError(f"output {out} already exists and is not an empty directory (pass --overwrite)")
    ps = probes if isinstance(probes, ProbeSet) else load_probe_set(probes)
    name = str(getattr(model, "name", type(model).__name__))
    kind = surprise_kind(model)
    ref = model_ref or f"{type(model).__module__}:{type(model).__qualname__}"
    ck_sha = sha256_path(Path(checkpoint)) if checkpoint else None
    sched = plan(ps.index, batch_size, seed)
    blinder = Blinder(ps, seed)
    place(model, rank_device(device))
    fields = {"model": ref, "class": f"{type(model).__module__}:{type(model).__qualname__}",
              "voe_version": __version__, "args": dict(model_args or {}), "name": name, "checkpoint_sha256": ck_sha,
              "manifest_sha256": ps.manifest_sha256, "batch_size": batch_size, "seed": seed,
              "surprise_kind": kind, "device": device, "bf16": bf16, "code_sha256": code_sha256(model)}
    if cache_root is None and ranks.world > 1:  # also for shards: the cache is the hand-over
        raise VoeError("sharded scoring needs a cache directory shared by every rank (--cache DIR)")
    cache = ScoreCache(cache_root, fields) if cache_root is not None else None
    if check:
        check_sample(model, blinder, sched)
    t0 = time.perf_counter()
    mine, computed = score_batches(model, blinder, sched, sched.for_rank(ranks.rank, ranks.world),
                                   cache=cache, device=device, bf16=bf16, progress=progress)
    computed = ranks.total(computed)  # a collective: every rank takes part
    wall = time.perf_counter() - t0
    if ranks.rank != 0 or ranks.launcher == "shard":
        return None  # a shard (SLURM array task) leaves its batches in the cache for a final run
    by_id = mine if ranks.world == 1 else _merge(sched, blinder, cache)
    index, nll = assemble(ps.index, by_id)
    meta = {
        "model": {"ref": ref, "class": fields["class"],
                  "args": dict(model_args or {}), "name": name,
                  "observation": str(getattr(model, "observation", "")),
                  "checkpoint": portable_ref(checkpoint, out) if checkpoint else None, "checkpoint_sha256": ck_sha,
                  "code_sha256": fields["code_sha256"], "training": _training(checkpoint)},
        "surprise_kind": kind,
        "probes": {"path": portable_ref(ps.path, out), "manifest_sha256": ps.manifest_sha256,
                   "concepts": list(ps.manifest.get("concepts", []))},
        "batch_size": batch_size, "device": device, "bf16": bool(bf16),
        "order": {"seed": seed, "n_batches": len(sched.batches), "n_groups": sched.n_groups,
                  "rule": "matched sets shuffled into groups of batch_size; batch j of a group holds "
                          "the j-th clip (shuffled) of each set (voe.scoring.order)"},
        "common_random_numbers": {"seed": seed, "rule": CRN_RULE},
        "check": "passed" if check else "skipped",
        "launcher": ranks.describe(), "clips_from_cache": len(index) - computed,
        "wall_time_s": round(wall, 3),
    }
    meta = write_run(out, index, nll, meta, overwrite=overwrite)
    if cache is not None:
        cache.clear()
    return meta
