"""Training: fit a learned model (or calibrate a reference) on a training set, with validation.

Why: one loop serves every learned model. Models expose ``prepare`` (clips as tensors)
and ``nll`` over windows of frames; state models train on windows of 2 frames (their inputs hold
the per-slot memory already), the pixel model on short windows through its recurrent memory.
References are "trained" by fitting their noise by maximum likelihood. Validation NLL is the mean
per-frame surprise (nats) over scored frames of held-out clips, the same number ``bench`` prints.

Memory does not grow with the training set: at most ``buffer_clips`` training clips are in memory
at a time (whole shards, see ``voe.models.clips``), validation streams in chunks, and references
calibrate on a seeded sample of at most ``buffer_clips`` clips.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from voe.errors import ProbeSetError, VoeError
from voe.io.batch import Batch
from voe.io.paths import portable_ref
from voe.io.probeset import ProbeSet, load_probe_set
from voe.models.clips import Clips, GroupSampler, MemoryClips, as_clips


@dataclass(frozen=True)
class TrainConfig:
    """How long and where to train (the architecture is the model's own config).

    ``steps`` is the budget: the learning-rate schedule depends on the step count only, so one
    seed gives one checkpoint whatever the machine's load (``None``: the model preset's
    ``steps``). ``minutes`` is only an outer safety cap; a run that hits it stops early and
    records ``time_capped`` in its checkpoint (its weights then depend on the machine's speed).
    """

    steps: int | None = None
    minutes: float | None = None
    device: str = "cpu"
    seed: int = 0
    val_frac: float = 0.1
    eval_every: int = 100
    threads: int = 1  # torch threads on CPU: on a shared 2-core machine one thread is fastest
    buffer_clips: int = 1024  # training clips in memory at once (a larger set is visited in groups)
    group_draws: int = 16  # windows drawn per buffered clip before the next group is loaded


def split_ids(ps: ProbeSet, val_frac: float, seed: int) -> tuple[list[str], list[str]]:
    """Training and validation clip ids (sorted) among a set's possible/training clips."""
    ids = list(ps.index.loc[ps.index.role != "impossible", "clip_id"])
    if len(ids) < 2:
        raise ProbeSetError(f"training set {ps.path} has {len(ids)} usable clip(s); need at least 2 "
                            f"(one for validation); generate more with `voe world generate --n N`")
    rng = np.random.default_rng(seed)
    order = [ids[i] for i in rng.permutation(len(ids))]
    n_val = min(len(ids) - 1, max(1, int(round(val_frac * len(ids)))))
    return sorted(order[n_val:]), sorted(order[:n_val])


def split_clips(data: Path, val_frac: float, seed: int) -> tuple[Clips, Clips, str]:
    """Training and validation clips (read from disk on demand) and the manifest hash."""
    ps = load_probe_set(data)
    tr, val = split_ids(ps, val_frac, seed)
    return Clips(ps, tr), Clips(ps, val), ps.manifest_sha256


def split_batches(data: Path, val_frac: float, seed: int) -> tuple[Batch, Batch, str]:
    """``split_clips`` loaded into two in-memory batches (small sets, tests and benches)."""
    tr, val, sha = split_clips(data, val_frac, seed)
    return tr.load(), val.load(), sha


def val_nll(model: Any, clips: Batch | Clips | MemoryClips, chunk: int = 64) -> float:
    """Mean per-frame surprise over scored frames, ``chunk`` clips in memory at a time."""
    parts = [model.frame_nll(b) for b in as_clips(clips).batches(chunk)]  # each (chunk, T)
    return float(np.nanmean(np.concatenate(parts)))


def _prepare(model: Any, clips: Clips | MemoryClips, ids: list[str], chunk: int = 128) -> dict:
    """``model.prepare`` of clips ``ids``, ``chunk`` clips read and converted at a time.

    Why chunks: the raw clips (frames above all) and the conversion's temporaries are several
    times the prepared tensors; only the latter need to stay for the whole group.
    """
    import torch

    if len(ids) <= chunk:
        return model.prepare(clips.load(ids))
    parts = [model.prepare(clips.load(ids[i:i + chunk])) for i in range(0, len(ids), chunk)]
    return {k: torch.cat([p[k] for p in parts]) for k in parts[0]}  # each (n, T, ...)


def _windows(data: dict, b: np.ndarray, t0: np.ndarray, L: int) -> dict:
    import torch

    bi = torch.from_numpy(b)[:, None]
    ti = torch.from_numpy(t0)[:, None] + torch.arange(L)[None]
    return {k: v[bi, ti] for k, v in data.items()}  # each (n, L, ...)


def fit(model: Any, train: Batch | Clips, val: Batch | Clips, cfg: TrainConfig,
        report: Callable[[int, float, float | None], None] | None = None) -> dict[str, Any]:
    """Train a ``TorchModel`` in place; keeps the weights with the best validation NLL.

    ``train`` and ``val`` are in-memory batches or ``Clips`` read from a set's shards; at most
    ``cfg.buffer_clips`` training clips are prepared at a time.
    """
    import torch

    if cfg.device == "cuda" and not torch.cuda.is_available():
        raise VoeError("--device cuda requested but torch sees no CUDA device; use --device cpu")
    preset = model.presets["cuda" if cfg.device == "cuda" else "cpu"]
    if cfg.device == "cpu" and cfg.threads:
        torch.set_num_threads(cfg.threads)
    torch.manual_seed(cfg.seed)
    rng = np.random.default_rng(cfg.seed)
    train = as_clips(train)
    groups = train.groups(cfg.buffer_clips)
    sampler = GroupSampler(groups, cfg.seed)
    ids = sampler.next()
    data, n_buf = _prepare(model, train, ids), len(ids)
    T = int(next(iter(data.values())).shape[1])
    per_group = max(1, math.ceil(n_buf * cfg.group_draws / preset["batch"]))  # steps per group
    L = min(preset["window"], T)
    model.net.to(cfg.device)
    opt = torch.optim.Adam(model.net.parameters(), lr=preset["lr"])
    steps = int(cfg.steps if cfg.steps is not None else preset["steps"])
    deadline = time.monotonic() + 60 * cfg.minutes if cfg.minutes is not None else float("inf")
    best, best_state, history, step, skipped = float("inf"), None, [], 0, 0
    start = time.monotonic()
    while step < steps and time.monotonic() < deadline:
        if len(groups) > 1 and step and step % per_group == 0:  # the next group of shards
            ids, data = sampler.next(), {}  # drop the old group before loading the next
            data, n_buf = _prepare(model, train, ids), len(ids)
        model.net.train()
        b = rng.integers(0, n_buf, preset["batch"])
        t0 = rng.integers(0, T - L + 1, preset["batch"])
        win = {k: v.to(cfg.device) for k, v in _windows(data, b, t0, L).items()}
        for g in opt.param_groups:  # linear decay to 5%: late steps refine the mean's precision
            g["lr"] = preset["lr"] * (1 - 0.95 * step / steps)
        loss = model.nll(win)[:, model.warmup:].mean()
        opt.zero_grad()
        loss.backward()
        norm = torch.nn.utils.clip_grad_norm_(model.net.parameters(), 10.0)
        if torch.isfinite(loss) and torch.isfinite(norm):
            opt.step()
        else:  # one non-finite batch once turned every weight into NaN for the rest of a demo run
            skipped += 1
            if skipped > max(10, step // 10):
                raise VoeError(f"training {getattr(model, 'name', 'model')} diverged: {skipped} of "
                               f"{step + 1} steps had a non-finite loss or gradient")
        step += 1
        loss = loss.item()
        v = None
        last = step >= steps or time.monotonic() >= deadline
        if step % cfg.eval_every == 0 or last:
            model.net.to("cpu")
            v = val_nll(model, val)
            model.net.to(cfg.device)
            history.append((step, float(loss), v))
            if v < best:
                best, best_state = v, copy.deepcopy(model.net.state_dict())
        if report:
            report(step, float(loss), v)
    model.net.to("cpu")
    if best_state is None:
        raise VoeError(f"training {getattr(model, 'name', 'model')} gave no finite validation NLL in "
                       f"{step} steps; no checkpoint written")
    model.net.load_state_dict({k: t.cpu() for k, t in best_state.items()})
    seconds = time.monotonic() - start
    return {"steps": step, "steps_budget": steps, "time_capped": step < steps, "seconds": seconds,
            "val_nll": best, "history": history, "skipped_steps": skipped,
            "train_frames_per_s": step * preset["batch"] * (L - model.warmup) / max(seconds, 1e-9),
            "train_groups": len(groups)}


def train(ref: str, data: Path, out: Path, cfg: TrainConfig, args: dict[str, Any] | None = None,
          report: Callable[[int, float, float | None], None] | None = None) -> dict[str, Any]:
    """Train (or calibrate) model ``ref`` on ``data`` and write a checkpoint to ``out``."""
    from voe.io.provenance import package_versions
    from voe.models.checkpoint import save_checkpoint
    from voe.models.loading import load_model, resolve

    full, _ = resolve(ref)
    train_c, val_c, sha = split_clips(data, cfg.val_frac, cfg.seed)
    args = dict(args or {})
    meta: dict[str, Any] = {"model": full, "seed": cfg.seed, "train_data": portable_ref(data, out),
                            "train_manifest_sha256": sha, "n_train": len(train_c), "n_val": len(val_c),
                            "versions": package_versions()}
    from voe.models.torchbase import TorchModel

    model = load_model(ref, {"seed": cfg.seed, **args} if _is_learned(full) else args)
    if isinstance(model, TorchModel):
        summary = fit(model, train_c, val_c, cfg, report)
        model.layout = model.batch_layout(train_c.load(train_c.ids[:2]))
        meta.update(config=model.config_dict(), feature_layout=model.layout, **summary)
        save_checkpoint(out, meta, model.weights())
        return meta
    if not hasattr(model, "calibrate"):
        raise VoeError(f"model '{ref}' is neither trainable nor calibratable")
    start = time.monotonic()
    calib = train_c.sample(cfg.buffer_clips, cfg.seed)  # a bounded, seeded sample of a large set
    model.calibrate(calib.load())
    v = val_nll(model, val_c)
    if report:
        report(1, v, v)
    meta.update(config=model.config(), feature_layout={"feature_names": list(train_c.ps.feature_names)},
                steps=1, seconds=time.monotonic() - start, val_nll=v, history=[], n_calibration=len(calib))
    save_checkpoint(out, meta)
    return meta


def _is_learned(full: str) -> bool:
    from voe.models import MODELS

    if ":" in full:
        return False
    return bool(MODELS.meta(full).get("learned"))
