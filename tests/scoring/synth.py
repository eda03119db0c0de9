"""A synthetic probe set written without the simulator: spliced noise quadruplets and pairs.

Why: scoring and report tests must not depend on the physics generators being healthy; any
clips with the right layout exercise the same code. Permanence-v1 gets quadruplets (AB and BA
splice A and B at the onset), Inertia-v1 gets possible/impossible pairs.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from voe.io.probeset import ClipRecord, write_probe_set

FEATURES = ("x", "y", "angle", "vx", "vy", "omega", "is_circle", "is_box", "width", "height", "intensity")
T, SIZE, K = 24, 16, 2


def _clip(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    frames = rng.integers(0, 256, size=(T, SIZE, SIZE), dtype=np.uint8)
    states = rng.normal(size=(T, K, len(FEATURES))).astype(np.float32)
    return frames, states


def make_probe_set(out: Path, n_sets: int = 6, seed: int = 0) -> Path:
    rng = np.random.default_rng(seed)
    recs = []
    for concept, kind in (("Permanence-v1", "quadruplet"), ("Inertia-v1", "pair")):
        name = concept.split("-v")[0].lower()
        for i in range(n_sets):
            set_id, onset = f"{name}-{i:04d}", int(rng.integers(8, 16))
            m = (np.arange(T) >= onset)[:, None, None]
            (fa, sa), (fb, sb) = _clip(rng), _clip(rng)
            if kind == "quadruplet":
                clips = {"A": (fa, sa), "B": (fb, sb), "AB": (np.where(m, fb, fa), np.where(m, sb, sa)),
                         "BA": (np.where(m, fa, fb), np.where(m, sa, sb))}
            else:
                clips = {"possible": (fa, sa), "impossible": (np.where(m, fb, fa), np.where(m, sb, sa))}
            for variant, (f, s) in clips.items():
                row = {"clip_id": f"{set_id}-{variant}", "concept": concept, "concept_name": name,
                       "set_id": set_id, "set_kind": kind, "variant": variant,
                       "role": "possible" if variant in ("A", "B", "possible") else "impossible",
                       "onset_frame": onset, "seed": seed + i, "visible_violation": bool(i % 2 == 0),
                       "n_distractors": int(i // 2 % 2), "params": json.dumps({"i": i}), "geometry": "{}"}
                recs.append(ClipRecord(row, f, s, np.ones((T, K), bool), np.ones((T, K), bool)))
    meta = {"kind": "probes", "concepts": ["Permanence-v1", "Inertia-v1"], "dt": 0.05, "n_frames": T,
            "frame_size": [SIZE, SIZE], "feature_names": list(FEATURES), "seed": seed}
    write_probe_set(out, recs, meta)
    return out
