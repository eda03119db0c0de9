"""The controls a report checks its verdicts against, for the probe set its runs were scored on.

Why computed by the report itself: the knowledge-free statistics, the stress test, frame copy's
flip count and track smoothness are statistics of the stored bytes, not models being re-run,
and take seconds (torch-free). Computing them from the very probe set the runs name (its
manifest hash checked) means no report can pair a verdict with controls from another probe set,
and none can skip them by forgetting a flag. Controls that need training or torch (random
networks, calibrated constant velocity, lesions) come from a stored ``voe validate-suite`` output
when one is given (``--validity``) and was run on the same probe set (same manifest hash).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from voe.controls.builtin import probe_set_controls
from voe.controls.confound import confounders, no_balanced_design
from voe.controls.matrix import specificity_matrix
from voe.controls.probe_runs import probe_set_runs, set_balance
from voe.errors import ProbeSetError, RunError
from voe.scoring.runs import Run
from voe.scoring.table import OPTIONAL_SET_KEYS


@dataclass(frozen=True)
class ControlCheck:
    """Control cells for a probe set, what they confound, and a note on what was not checked."""

    matrix: pd.DataFrame
    confounds: pd.DataFrame
    note: str


def read_matrix(validity: Path) -> tuple[pd.DataFrame, str]:
    """``matrix.csv`` of a ``voe validate-suite`` output and the probe manifest hash it was run on."""
    path = Path(validity) / "matrix.csv"
    if not path.exists():
        raise RunError(f"{path} is missing; run `voe validate-suite --out {validity}` first")
    matrix = pd.read_csv(path)
    for col in ("as_declared", "could_fail", "carries_verdict"):
        if col in matrix.columns:
            matrix[col] = matrix[col].map({True: True, False: False, "True": True, "False": False})
    prov = Path(validity) / "provenance.json"
    sha = json.loads(prov.read_text()).get("probes_manifest_sha256", "") if prov.exists() else ""
    return matrix, sha


def enrich_runs(runs: Sequence[Run], index: pd.DataFrame) -> None:
    """Give runs scored before the index had them its per-set columns (condition, whether it
    carries the verdict, no balanced design), matched by clip id, in place."""
    cols = [c for c in OPTIONAL_SET_KEYS if c in index.columns]
    for run in runs:
        missing = [c for c in cols if c not in run.clips.columns]
        if missing:
            extra = index.set_index("clip_id")[missing].reindex(run.clips["clip_id"].to_numpy())
            run.clips = pd.concat([run.clips, extra.reset_index(drop=True)], axis=1)


def check_probe_set(probes: Path, manifest_sha256: str, validity: Path | None = None,
                    n_boot: int = 10_000, runs: Sequence[Run] = ()) -> ControlCheck:
    """Compute the probe-set controls (and add a matching stored validity matrix); ``runs`` of
    this probe set get its per-set columns if they lack them (``enrich_runs``)."""
    from voe.io.probeset import load_probe_set

    try:
        ps = load_probe_set(probes)
    except ProbeSetError as exc:
        empty = pd.DataFrame(columns=["concept", "condition", "confounded", "by"])
        return ControlCheck(pd.DataFrame(), empty, f"controls were not computed ({exc}); no verdict "
                                                    "was checked for confounds")
    if ps.manifest_sha256 != manifest_sha256:
        raise RunError(f"the probe set at {probes} has changed since scoring (manifest hash differs); "
                       "its controls would not describe the scored clips: re-score or restore it")
    enrich_runs(runs, ps.index)
    controls = probe_set_controls()
    matrix = specificity_matrix(controls, probe_set_runs(ps, controls), n_boot=n_boot, balance=set_balance(ps))
    note = ("Controls computed from the probe set itself: " + ", ".join(c.name for c in controls) + ".")
    if validity is not None:
        stored, sha = read_matrix(validity)
        if sha == manifest_sha256:
            extra = stored[~stored["control"].isin(matrix["control"])]
            matrix = pd.concat([matrix, extra], ignore_index=True)
            note += f" Added from {validity}: {extra['control'].nunique()} stored controls."
        else:
            note += (f" The validity run {validity} was made on another probe set, so its controls "
                     "do not enter the confound check.")
    conf = confounders(matrix, no_balanced_design(ps.index))
    return ControlCheck(matrix, conf, note)
