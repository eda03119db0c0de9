"""``check_model``: does a model keep the ``frame_nll`` contract? (like scikit-learn's check_estimator)

Why: every model, built-in or a user's, is scored by the same engine; a model that returns the
wrong shape, NaN where it must score, or depends on what else is in the batch would silently
corrupt the metrics. These checks catch that before any number is reported.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.errors import ModelContractError
from voe.io.batch import Batch

RTOL, ATOL = 1e-4, 1e-3


def _nll(model: Any, batch: Batch, what: str) -> np.ndarray:
    name = getattr(model, "name", type(model).__name__)
    try:
        out = model.frame_nll(batch)
    except ModelContractError:
        raise
    except Exception as exc:
        raise ModelContractError(f"model '{name}': frame_nll raised {type(exc).__name__}: {exc} ({what})") from exc
    try:
        out = np.asarray(out, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ModelContractError(f"model '{name}': frame_nll returned {type(out).__name__}, "
                                 f"not an array of numbers ({what})") from exc
    if out.shape != batch.shape:
        raise ModelContractError(f"model '{name}': frame_nll returned shape {out.shape}, expected "
                                 f"(B, T) = {batch.shape} ({what})")
    return out


def check_model(model: Any, batch: Batch) -> None:
    """Raise ``ModelContractError`` naming the model and what broke; return None if it is fine.

    Checks: shape ``(B, T)``; values finite except NaN for warm-up frames, which must be a prefix
    of frames that is the same for every clip; at least one scored frame; determinism (scoring
    twice gives the same numbers); batch-size invariance (scoring the two halves of the batch
    separately gives the same numbers as scoring it whole).
    """
    name = getattr(model, "name", type(model).__name__)
    if len(batch) < 2:
        raise ValueError("check_model needs a batch of at least 2 clips")
    full = _nll(model, batch, "whole batch")
    nan = np.isnan(full)
    if np.isinf(full).any():
        b, t = np.argwhere(np.isinf(full))[0]
        raise ModelContractError(f"model '{name}': infinite surprise at clip {b}, frame {t}")
    mixed = nan.any(0) & ~nan.all(0)  # (T,) frames NaN in some clips only
    if mixed.any():
        t = int(np.argmax(mixed))
        majority = nan[:, t].mean() > 0.5
        b = int(np.argmax(nan[:, t] != majority))
        raise ModelContractError(f"model '{name}': NaN at clip {b}, frame {t} but not in every clip; "
                                 f"NaN is only allowed for the same warm-up frames in every clip")
    cols = nan[0]
    warm = int(np.argmin(cols)) if not cols.all() else len(cols)
    if cols.all():
        raise ModelContractError(f"model '{name}': every frame is NaN; nothing is scored")
    if cols[warm:].any():
        t = warm + int(np.argmax(cols[warm:]))
        raise ModelContractError(f"model '{name}': NaN at frame {t} after scored frames; NaN is only "
                                 f"allowed for warm-up frames at the start of a clip")
    again = _nll(model, batch, "second call")
    if not np.allclose(full, again, rtol=RTOL, atol=ATOL, equal_nan=True):
        d = np.nanmax(np.abs(full - again))
        raise ModelContractError(f"model '{name}': not deterministic; scoring the same batch twice "
                                 f"differs by up to {d:.3g} nats")
    h = len(batch) // 2
    halves = np.concatenate([_nll(model, batch.take(slice(0, h)), "first half"),
                             _nll(model, batch.take(slice(h, None)), "second half")])
    if not np.allclose(full, halves, rtol=RTOL, atol=ATOL, equal_nan=True):
        d = np.nanmax(np.abs(full - halves))
        raise ModelContractError(f"model '{name}': not batch-size invariant; scoring halves of the batch "
                                 f"differs from scoring it whole by up to {d:.3g} nats")
