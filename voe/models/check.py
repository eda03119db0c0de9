"""``check_model``: does a model keep the ``frame_nll`` contract? (like scikit-learn's check_estimator)

Why: every model, built-in or a user's, is scored by the same engine; a model that returns the
wrong shape, NaN where it must score, depends on what else is in the batch, reads the clip keys or
looks at frames it has not been shown yet would silently corrupt the metrics. The harness is
blind (opaque keys, shuffled order), so such a model is at chance rather than perfect, but a
verdict must not rest on that: these checks reject it by name before any number is reported.

Checks, in order (each failure is one line naming the check): ``contract`` (shape, finite values,
NaN only as a common warm-up prefix), ``determinism``, ``order`` (permuting the clips permutes the
answer), ``identifiers`` (renaming the clip keys changes nothing), ``batch size`` (scoring halves
gives the same numbers) and ``causality`` (``frame_nll[:, :t]`` is unchanged when frames, states
and presence from ``t`` on are replaced).
"""

from __future__ import annotations

import dataclasses
import hashlib
from typing import Any

import numpy as np

from voe.errors import ModelContractError
from voe.io.batch import Batch

RTOL, ATOL = 1e-4, 1e-3
CHECKS = ("contract", "determinism", "order", "identifiers", "batch size", "causality")


def _name(model: Any) -> str:
    return str(getattr(model, "name", type(model).__name__))


def _fail(model: Any, check: str, why: str) -> ModelContractError:
    return ModelContractError(f"model '{_name(model)}' failed the {check} check: {why}")


def _nll(model: Any, batch: Batch, what: str) -> np.ndarray:
    try:
        out = model.frame_nll(batch)
    except ModelContractError:
        raise
    except Exception as exc:
        raise ModelContractError(f"model '{_name(model)}': frame_nll raised {type(exc).__name__}: {exc} "
                                 f"({what})") from exc
    try:
        out = np.asarray(out, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise _fail(model, "contract", f"frame_nll returned {type(out).__name__}, not an array of "
                                       f"numbers ({what})") from exc
    if out.shape != batch.shape:
        raise _fail(model, "contract", f"frame_nll returned shape {out.shape}, expected (B, T) = "
                                       f"{batch.shape} ({what})")
    return out


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.allclose(a, b, rtol=RTOL, atol=ATOL, equal_nan=True))


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    if (np.isnan(a) != np.isnan(b)).any():
        return float("inf")  # NaN (unscored) in one, a number in the other
    d = np.abs(a - b)[~np.isnan(a)]
    return float(d.max()) if d.size else 0.0


def _check_values(model: Any, full: np.ndarray) -> None:
    nan = np.isnan(full)  # (B, T)
    if np.isinf(full).any():
        b, t = np.argwhere(np.isinf(full))[0]
        raise _fail(model, "contract", f"infinite surprise at clip {b}, frame {t}")
    mixed = nan.any(0) & ~nan.all(0)  # (T,) frames NaN in some clips only
    if mixed.any():
        t = int(np.argmax(mixed))
        majority = nan[:, t].mean() > 0.5
        b = int(np.argmax(nan[:, t] != majority))
        raise _fail(model, "contract", f"NaN at clip {b}, frame {t} but not in every clip; NaN is only "
                                       "allowed for the same warm-up frames in every clip")
    cols = nan[0]
    if cols.all():
        raise _fail(model, "contract", "every frame is NaN; nothing is scored")
    warm = int(np.argmin(cols))
    if cols[warm:].any():
        t = warm + int(np.argmax(cols[warm:]))
        raise _fail(model, "contract", f"NaN at frame {t} after scored frames; NaN is only allowed for "
                                       "warm-up frames at the start of a clip")


def _renamed(batch: Batch) -> Batch:
    keys = tuple(hashlib.sha256(f"voe-check:{k}".encode()).hexdigest()[:16] for k in batch.clip_ids)
    if not batch.clip_ids:
        keys = tuple(hashlib.sha256(f"voe-check:{i}".encode()).hexdigest()[:16] for i in range(len(batch)))
    return dataclasses.replace(batch, clip_ids=keys)


def _future_changed(batch: Batch, t: int) -> Batch:
    """``batch`` with frames, states and presence from frame ``t`` on taken from the next clip."""
    def swap(arr: np.ndarray) -> np.ndarray:
        out = np.array(arr, copy=True)
        out[:, t:] = np.roll(arr, 1, axis=0)[:, t:]
        return out

    return dataclasses.replace(batch, frames=swap(batch.frames), states=swap(batch.states),
                               present=swap(batch.present))


def check_model(model: Any, batch: Batch) -> None:
    """Raise ``ModelContractError`` naming the model and the failed check; return None if fine.

    Args:
        model: anything following ``voe.models.protocol.Model``.
        batch: at least 2 clips (ideally from different matched sets, as the harness builds them
            with ``voe.scoring.order.Blinder``); 4 or more make the order check stronger.
    """
    if len(batch) < 2:
        raise ValueError("check_model needs a batch of at least 2 clips")
    B, T = batch.shape
    full = _nll(model, batch, "whole batch")  # (B, T)
    _check_values(model, full)
    again = _nll(model, batch, "second call")
    if not _same(full, again):
        raise _fail(model, "determinism", f"scoring the same batch twice differs by up to "
                                          f"{_gap(full, again):.3g}")
    perm = np.roll(np.arange(B), 1)  # every clip moves (also for B = 2)
    shuffled = _nll(model, batch.take(perm), "clips in another order")
    if not _same(full[perm], shuffled):
        raise _fail(model, "order", f"scoring the same clips in another order changes a clip's surprise "
                                    f"by up to {_gap(full[perm], shuffled):.3g}; surprise must not "
                                    "depend on a clip's position in the batch")
    renamed = _nll(model, _renamed(batch), "clips under other keys")
    if not _same(full, renamed):
        raise _fail(model, "identifiers", f"renaming the clips changes their surprise by up to "
                                          f"{_gap(full, renamed):.3g}; batch.clip_ids are opaque keys "
                                          "for messages only and must not be read")
    h = B // 2
    halves = np.concatenate([_nll(model, batch.take(slice(0, h)), "first half"),
                             _nll(model, batch.take(slice(h, None)), "second half")])
    if not _same(full, halves):
        raise _fail(model, "batch size", f"scoring halves of the batch differs from scoring it whole by "
                                         f"up to {_gap(full, halves):.3g}")
    for t in sorted({max(1, T // 3), max(1, 2 * T // 3)}):
        if t >= T:
            continue
        later = _nll(model, _future_changed(batch, t), f"frames from {t} on changed")
        if not _same(full[:, :t], later[:, :t]):
            raise _fail(model, "causality", f"changing frames, states and presence from frame {t} on "
                                            f"changes the surprise of earlier frames by up to "
                                            f"{_gap(full[:, :t], later[:, :t]):.3g}; frame_nll[:, t] may "
                                            "use frames 0..t only")
