"""``load_model``: one entry point from a name or ``package.module:attr`` to a scoreable model.

Why: the CLI, the scoring engine and users all get a model the same way, so a registered name,
a user's class or factory, model arguments and a checkpoint compose identically everywhere.
"""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

from voe.errors import CheckpointError, ModelContractError, UnknownNameError, VoeError
from voe.registry import load_ref


def resolve(ref: str) -> tuple[str, Any]:
    """``(model id or ref, class/factory)`` for a registered name or ``module:attr``."""
    from voe.models import MODELS

    if ":" in ref:
        import os
        import sys

        if os.getcwd() not in sys.path and "" not in sys.path:
            sys.path.append(os.getcwd())  # like `python -m`: user modules next to the data
        return ref, load_ref(ref)
    full = MODELS.resolve(ref)  # did-you-mean on typos
    return full, MODELS.get(full)


def _construct(ref: str, factory: Any, args: dict[str, Any]) -> Any:
    if not inspect.isclass(factory) and hasattr(factory, "frame_nll"):
        if args:
            raise VoeError(f"'{ref}' is a model instance; it takes no --model-arg ({sorted(args)})")
        return factory  # already a model
    if not callable(factory):
        raise UnknownNameError(f"'{ref}' is neither a model class, a factory nor a model")
    try:
        return factory(**args)
    except TypeError as exc:
        raise VoeError(f"cannot construct model '{ref}' with arguments {args}: {exc}") from exc


def validate_protocol(model: Any, ref: str) -> Any:
    """Check that ``model`` has ``name``, ``observation`` and ``frame_nll``."""
    missing = [a for a in ("name", "observation", "frame_nll") if not hasattr(model, a)]
    if missing:
        raise ModelContractError(f"model '{ref}' lacks {', '.join(missing)} (see the model protocol in docs/models.md)")
    if model.observation not in ("frames", "states"):
        raise ModelContractError(f"model '{ref}': observation must be 'frames' or 'states', got {model.observation!r}")
    return model


def load_model(ref: str, args: dict[str, Any] | None = None, checkpoint: Path | None = None) -> Any:
    """Build a model by registered name or ``package.module:attr``, optionally from a checkpoint.

    Args:
        ref: ``constvel``, ``interaction-v3``, ``mypkg.sim:MyModel`` ...
        args: keyword arguments for the class or factory (``--model-arg k=v``).
        checkpoint: a directory written by ``voe train`` (config and weights).

    Raises:
        UnknownNameError: unknown name or unimportable reference.
        CheckpointError: missing checkpoint, or one written for another model or architecture.
        ModelContractError: the object does not implement the protocol.
    """
    args = dict(args or {})
    full, factory = resolve(ref)
    if checkpoint is None:
        return validate_protocol(_construct(ref, factory, args), ref)
    from voe.models.checkpoint import load_tensors, read_checkpoint

    meta = read_checkpoint(Path(checkpoint))
    if meta["model"] != full:
        raise CheckpointError(f"checkpoint {checkpoint} was trained for model '{meta['model']}', not '{full}'")
    config = dict(meta["config"])
    clash = {k: v for k, v in args.items() if k in config and config[k] != v}
    if clash:
        raise CheckpointError(f"checkpoint {checkpoint} has {({k: config[k] for k in clash})}, "
                              f"which --model-arg {clash} would change; retrain instead")
    try:
        model = _construct(ref, factory, {**config, **args})
    except VoeError as exc:  # a damaged config.json: name the file, not just the arguments
        raise CheckpointError(f"{Path(checkpoint) / 'config.json'}: {exc}") from exc
    if hasattr(model, "load_weights"):
        model.load_weights(load_tensors(Path(checkpoint)), str(checkpoint))
        model.layout = meta.get("feature_layout")
    return validate_protocol(model, ref)
