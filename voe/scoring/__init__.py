"""Scoring: run a model over a probe set once, then compute metrics and verdicts from the stored run.

Why: storing raw per-frame surprise once (``frames.parquet``) means metrics, statistics and reports
are recomputed from disk, never by re-running a model.
"""

from voe.scoring.external import score_surprises
from voe.scoring.runs import Run, load_run, load_runs
from voe.scoring.score import score_probe_set

__all__ = ["Run", "load_run", "load_runs", "score_probe_set", "score_surprises"]
