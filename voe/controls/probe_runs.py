"""Controls computed from a probe set's stored bytes, as in-memory runs, and each set's balance.

Why in-memory runs: the knowledge-free statistics, the stress test and the two physics-poor
statistics (frame copy's flip count, track smoothness) are not models being re-run; they are
statistics of the stored frames and states, cheap enough (seconds) that ``voe report`` computes
them from the probe set the runs were scored on, and ``voe validate-suite`` uses the same code.
They become ``Run`` objects so the specificity matrix treats them like any scored model.

The balance of each matched set (which multisets its impossible clips share with its possible
ones: F frames, M per-step changes, S per-frame object states) is computed here too, because
it decides which control cells could not have failed: a scorer that only sees what a balance
equalises ties on every such set by construction.
"""

from __future__ import annotations

import hashlib
from collections import Counter
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
import pandas as pd

from voe.controls.smoothness import Smoothness
from voe.controls.spec import Control
from voe.controls.statistics import STATISTICS, Statistic, StatTraces, concept_chunks, statistic_traces
from voe.io.probeset import ProbeSet
from voe.scoring.runs import Run

#: Frame copy's binarisation threshold (``voe.models.framecopy.THRESHOLD``; a test keeps them
#: equal), repeated so that reports need not import the model layer.
FRAMECOPY_THRESHOLD = 128


class FlipCount(Statistic):
    """Frame copy's evidence: bits that flip between frames (binarised at frame copy's threshold).

    Frame copy's surprise is ``a + flips * log((1 - eps) / eps)`` per frame, an increasing affine
    function of this count for any ``eps < 1/2``, so its matched-set accuracy is frame copy's.
    """

    name: ClassVar[str] = "framecopy"
    invariant_to: ClassVar[str] = ""
    why: ClassVar[str] = "frame copy: pixels persist, so it may notice changes in plain view only"

    def traces(self, arrays, names):
        bits = arrays["frames"] >= FRAMECOPY_THRESHOLD  # (B, T, H, W)
        out = np.full(bits.shape[:2], np.nan)
        out[:, 1:] = (bits[:, 1:] != bits[:, :-1]).sum(axis=(2, 3))
        return out


#: name -> statistic of the stored bytes ("stat:NAME" in a control's model).
PROBE_STATISTICS: dict[str, type[Statistic]] = {**STATISTICS, "smoothness": Smoothness, "framecopy": FlipCount}
STRESS = ("stress-frame", "stress-step")


def is_probe_statistic(model: str) -> bool:
    """Is ``model`` (a control's model ref) computed from the probe set rather than scored?"""
    return model.startswith("stat:") and (model[5:] in PROBE_STATISTICS or model[5:] in STRESS)


def statistic(ps: ProbeSet, model: str) -> StatTraces:
    """Traces of the probe statistic ``stat:NAME`` over every clip of ``ps``."""
    name = model.removeprefix("stat:")
    if name in STRESS:
        from voe.controls.stress import stress_traces

        return stress_traces(ps, name.split("-")[1])
    return statistic_traces(ps, PROBE_STATISTICS[name]())


def as_run(ps: ProbeSet, traces: np.ndarray, label: str, ref: str) -> Run:
    """An in-memory ``Run`` of per-frame ``traces (N, T)`` over ``ps`` (clips in index order)."""
    clips = ps.index.drop(columns=[c for c in ("geometry", "params") if c in ps.index.columns]).copy()
    clips = clips.reset_index(drop=True)
    with np.errstate(all="ignore"):
        clips["sum"] = np.nansum(traces, 1)
        clips["max"] = np.nanmax(np.where(np.isnan(traces), -np.inf, traces), 1)
        clips["n_scored"] = (~np.isnan(traces)).sum(1)
        onset = clips["onset_frame"].to_numpy()
        post = np.arange(traces.shape[1])[None] >= onset[:, None]
        clips["mean_post"] = np.nanmean(np.where(post, traces, np.nan), 1)
    meta = {"probes": {"manifest_sha256": ps.manifest_sha256, "path": str(ps.path)},
            "model": {"name": label, "ref": ref, "args": {}, "observation": "probe statistic"}}
    return Run(ps.path, meta, clips, traces, label)


def probe_set_runs(ps: ProbeSet, controls: Sequence[Control]) -> list[Run]:
    """One in-memory run per control whose model is a probe statistic (``stat:NAME``)."""
    return [as_run(ps, statistic(ps, c.model).traces, c.name, c.model) for c in controls]


def _digests(x: np.ndarray) -> list[bytes]:
    return [hashlib.sha1(np.ascontiguousarray(f).tobytes()).digest() for f in x]


def set_balance(ps: ProbeSet) -> pd.DataFrame:
    """Per matched set: does it reach F (frames), M (per-step change) and S (per-frame states)?

    Each is an exact multiset equality over the stored bytes between the impossible and the
    possible clips of the set (states with hidden slots masked, as models see them).
    """
    rows = []
    for concept, idx_rows, arrays in concept_chunks(ps):
        idx = ps.index.iloc[idx_rows].reset_index(drop=True)
        f = arrays["frames"]  # (B, T, H, W)
        step = np.abs(f[:, 1:].astype(np.int16) - f[:, :-1]).astype(np.uint8)  # (B, T-1, H, W)
        st = np.where(arrays["present"][..., None], arrays["states"], np.nan)  # (B, T, K, F)
        for sid, g in idx.groupby("set_id", sort=True):
            imp = (g["role"] == "impossible").to_numpy()
            b = g.index.to_numpy()

            def same(x: np.ndarray, b=b, imp=imp) -> bool:
                return Counter(d for i in b[imp] for d in _digests(x[i])) == \
                    Counter(d for i in b[~imp] for d in _digests(x[i]))

            rows.append({"concept": concept, "set_id": sid, "F": same(f), "M": same(step), "S": same(st)})
    return pd.DataFrame(rows)
