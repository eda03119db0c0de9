"""Checkpoints: a directory with ``weights.safetensors`` and ``config.json``, written atomically.

Why: loading must never unpickle (safetensors holds only tensors), and a checkpoint must say
exactly what it is: the model id and config (architecture), the training seed, the sha256 of the
training set's manifest and the feature layout, so that loading it into another architecture or
scoring it on another feature layout fails with a ``CheckpointError`` instead of a silent mess.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from voe.errors import CheckpointError
from voe.io import jsonio
from voe.io.atomic import atomic_dir
from voe.io.paths import inside

FORMAT = "voe-checkpoint-1"
WEIGHTS, CONFIG = "weights.safetensors", "config.json"


def save_checkpoint(out: Path, meta: dict[str, Any], tensors: dict[str, Any] | None = None) -> Path:
    """Write ``meta`` (must hold ``model`` and ``config``) and ``tensors`` to directory ``out``.

    ``tensors`` may be torch tensors or numpy arrays; reference models pass none.
    """
    tensors = tensors or {}
    with atomic_dir(Path(out), overwrite=True) as tmp:
        if tensors and not isinstance(next(iter(tensors.values())), np.ndarray):
            from safetensors.torch import save_file
        else:
            from safetensors.numpy import save_file
        save_file(tensors, str(tmp / WEIGHTS))
        (tmp / CONFIG).write_text(jsonio.dumps({"format": FORMAT, **meta}, indent=1, sort_keys=True) + "\n")
    return Path(out)


def read_checkpoint(path: Path) -> dict[str, Any]:
    """The checkpoint's ``config.json`` (weights are loaded separately by ``load_tensors``)."""
    path = Path(path)
    cfg = path / CONFIG
    if not path.exists():
        raise CheckpointError(f"checkpoint {path} does not exist; train one with `voe train MODEL --out {path}`")
    if not cfg.exists():
        raise CheckpointError(f"{path} is not a voe checkpoint (no {CONFIG}); expected a directory from `voe train`")
    try:
        meta = json.loads(inside(path, CONFIG, path, CheckpointError).read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise CheckpointError(f"{cfg} is not valid JSON: {exc}") from exc
    if not isinstance(meta, dict) or meta.get("format") != FORMAT or "model" not in meta or "config" not in meta:
        raise CheckpointError(f"{cfg} is not a {FORMAT} checkpoint config")
    if not isinstance(meta["model"], str) or not isinstance(meta["config"], dict):
        raise CheckpointError(f"{cfg}: 'model' must be a string and 'config' an object (got "
                              f"{type(meta['model']).__name__} and {type(meta['config']).__name__})")
    if not all(isinstance(k, str) for k in meta["config"]):
        raise CheckpointError(f"{cfg}: 'config' keys must be strings")
    return meta


TRAINING_KEYS = ("steps", "steps_budget", "time_capped", "val_nll", "seed", "train_manifest_sha256", "n_calibration")


def training_record(path: Path) -> dict[str, Any] | None:
    """How the checkpoint at ``path`` was trained, for a scoring run to store beside its results.

    Why: a report is built from stored runs only, and a model that ``voe train`` stopped at its
    wall-time cap (``time_capped``: its weights depend on the machine's speed) must be named there;
    a demo on a loaded machine once reported a capped ``interaction`` model without saying so.

    Returns:
        The keys of ``TRAINING_KEYS`` that the checkpoint's config records, or ``None`` when ``path``
        is not a voe checkpoint directory (a user's own weights file, say).
    """
    try:
        meta = read_checkpoint(Path(path))
    except CheckpointError:
        return None
    return {k: meta[k] for k in TRAINING_KEYS if k in meta}


def load_tensors(path: Path) -> dict[str, Any]:
    """Torch tensors from ``weights.safetensors`` (no pickle)."""
    from safetensors import SafetensorError
    from safetensors.torch import load_file

    w = Path(path) / WEIGHTS
    if not w.exists():
        raise CheckpointError(f"checkpoint {path} lacks {WEIGHTS}")
    inside(path, WEIGHTS, Path(path) / CONFIG, CheckpointError)
    try:
        return load_file(str(w))
    except (SafetensorError, OSError, ValueError) as exc:
        raise CheckpointError(f"{w} cannot be read: {exc}") from exc
