"""Generate a probe set: every matched set of every requested concept, in parallel, to disk.

Why: generation is embarrassingly parallel over (concept, set index), and each set is seeded from
``(seed, concept id, set index)`` alone, so the output is byte-identical whatever ``jobs`` is.
Sets stream from ``parallel_map`` (in order) into the shard writer, so memory does not grow with
the number of sets.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

from voe import __version__
from voe.concepts import CONCEPTS, SUITES, get_concept
from voe.concepts.base import MatchedSet
from voe.errors import ConceptError
from voe.io.probeset import ClipRecord, write_probe_set
from voe.io.provenance import package_versions
from voe.parallel import parallel_map
from voe.sim.scene import FEATURE_NAMES, SimConfig


def resolve_concepts(suite: str | None = None, concepts: Sequence[str] | None = None) -> list[str]:
    """Concept ids from a suite name and/or explicit names (did-you-mean on typos)."""
    names: list[str] = []
    if suite:
        if suite not in SUITES:
            from voe.errors import UnknownNameError

            raise UnknownNameError(f"unknown suite '{suite}' (known: {', '.join(SUITES)})")
        names += SUITES[suite]
    names += list(concepts or [])
    ids = [CONCEPTS.resolve(n) for n in names]
    return list(dict.fromkeys(ids))


def set_records(mset: MatchedSet) -> list[ClipRecord]:
    """Index rows and arrays for the clips of one matched set."""
    name = mset.concept.split("-v")[0].lower()
    set_id = f"{name}-{mset.set_index:04d}"
    out = []
    for clip in mset.clips:
        row = {
            "clip_id": f"{set_id}-{clip.variant}", "concept": mset.concept, "concept_name": name,
            "set_id": set_id, "set_kind": mset.kind, "variant": clip.variant, "role": clip.role,
            "onset_frame": int(clip.onset), "seed": int(mset.seed),
            "visible_violation": bool(mset.visible), "n_distractors": int(mset.n_distractors),
            "condition": mset.condition, "carries_verdict": bool(mset.carries_verdict),
            "balance_claim": mset.balance_claim, "confounded": bool(mset.confounded),
            "params": json.dumps(mset.params, sort_keys=True),
            "geometry": json.dumps(clip.rec.geometry, sort_keys=True),
        }
        out.append(ClipRecord(row, clip.rec.frames, clip.rec.states, clip.rec.present, clip.rec.exists))
    return out


def _make(job: tuple[str, int, int, SimConfig]) -> list[ClipRecord]:
    concept_id, index, seed, cfg = job
    try:
        return set_records(get_concept(concept_id).make_set(index, seed, cfg))
    except ConceptError:
        raise
    except Exception as exc:  # a generator bug: name the set so it can be reproduced
        raise ConceptError(f"{concept_id} set {index} (seed {seed}) failed: {exc!r}") from exc


def generate_records(concept_ids: Sequence[str], per_concept: int, seed: int, cfg: SimConfig,
                     jobs: int = 1, progress: Callable[[int], None] | None = None) -> Iterator[ClipRecord]:
    """All clip records, ordered by concept then set index, as they are made (a lazy iterator)."""
    work = [(cid, i, seed, cfg) for cid in concept_ids for i in range(per_concept)]
    for recs in parallel_map(_make, work, jobs, progress):
        yield from recs


def manifest_meta(kind: str, concept_ids: Sequence[str], seed: int, cfg: SimConfig,
                  extra: dict[str, Any] | None = None) -> dict[str, Any]:
    """Manifest fields shared by probe sets and training sets (no timestamps: determinism)."""
    return {
        "kind": kind, "voe_version": __version__,
        "versions": package_versions(("numpy", "pandas", "pyarrow", "pymunk")),
        "seed": seed, "concepts": list(concept_ids), "sim": asdict(cfg),
        "dt": cfg.dt, "frame_size": [cfg.size, cfg.size], "n_frames": cfg.n_frames,
        "n_slots": cfg.n_slots, "feature_names": list(FEATURE_NAMES), **(extra or {}),
    }


def generate_probe_set(out: Path, concept_ids: Sequence[str], per_concept: int, seed: int,
                       cfg: SimConfig, jobs: int = 1, overwrite: bool = False,
                       progress: Callable[[int], None] | None = None) -> dict[str, Any]:
    """Generate and write a probe set; returns its manifest."""
    records = generate_records(concept_ids, per_concept, seed, cfg, jobs, progress)
    meta = manifest_meta("probes", concept_ids, seed, cfg, {"per_concept": per_concept})
    return write_probe_set(out, records, meta, overwrite=overwrite)
