"""A report on a probe set that gives its answer away: verdicts confounded, controls shown."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from voe.io.probeset import ClipRecord, write_probe_set
from voe.report.build import build_report
from voe.scoring.score import score_probe_set
from voe.testing import PixelSumModel

FEATURES = ("x", "y", "angle", "vx", "vy", "omega", "is_circle", "is_box", "width", "height", "intensity")
T, SIZE, N_SETS = 12, 16, 12


def _giveaway_probes(out: Path) -> Path:
    """Pairs whose impossible clip turns brighter at the onset: any single frame gives it away.
    A second concept is flagged as having no balanced design."""
    rng = np.random.default_rng(0)
    recs = []
    for concept, flagged in (("Bright-v1", False), ("Flagged-v1", True)):
        for i in range(N_SETS):
            base = rng.integers(0, 100, size=(T, SIZE, SIZE), dtype=np.uint8)
            imp = base.copy()
            imp[6:] += 120
            states = rng.normal(size=(T, 1, len(FEATURES))).astype(np.float32)
            for role, f in (("possible", base), ("impossible", imp if not flagged else base[::-1].copy())):
                row = {"clip_id": f"{concept}-{i}-{role}", "concept": concept, "concept_name": concept[:-3].lower(),
                       "set_id": f"{concept.lower()}-{i:04d}", "set_kind": "pair", "variant": role, "role": role,
                       "onset_frame": 6, "seed": i, "visible_violation": bool(i % 2),
                       "n_distractors": 0, "params": "{}", "geometry": "{}", "condition": ["occluded", "visible"][i % 2],
                       "carries_verdict": True, "confounded": flagged}
                recs.append(ClipRecord(row, f, states, np.ones((T, 1), bool), np.ones((T, 1), bool)))
    meta = {"kind": "probes", "concepts": ["Bright-v1", "Flagged-v1"], "dt": 0.05, "n_frames": T,
            "frame_size": [SIZE, SIZE], "feature_names": list(FEATURES), "seed": 0}
    write_probe_set(out, recs, meta)
    return out


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("giveaway")
    probes = _giveaway_probes(root / "probes")
    score_probe_set(PixelSumModel(), probes, root / "run")
    build_report([root / "run"], root / "report", n_boot=500)
    return root / "report"


def test_a_perfect_model_is_confounded_where_a_knowledge_free_control_separates_the_clips(report):
    s = pd.read_csv(report / "summary.csv").set_index("concept")
    assert s.loc["Bright-v1", "accuracy"] == 1.0 and s.loc["Bright-v1", "raw_verdict"] == "learned"
    assert s.loc["Flagged-v1", "accuracy"] == 0.5  # the time-reversed twin holds the same frames
    assert (s["verdict"] == "confounded").all()
    why = s.loc["Bright-v1", "confounded_by"]
    assert "density 0.00 [0.00, 0.00]" in why and "stress-frame 1.00" in why  # either direction
    assert s.loc["Flagged-v1", "confounded_by"].startswith("declares no balanced design")
    controls = pd.read_csv(report / "controls.csv")
    assert {"density", "motion-energy", "stress-frame", "framecopy", "smoothness"} <= set(controls["control"])
    md = (report / "report.md").read_text()
    assert "Can the probes tell?" in md and "confounded" in md and "stress-frame 1.00" in md
    assert "decisive from 6 verdict-carrying sets per concept; the smallest concept here has 12." in md
