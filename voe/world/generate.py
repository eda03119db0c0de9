"""Generate a training set: ordinary (or counterfactual) physics clips, in parallel, to disk.

Why: models must be trainable *without* a concept for the validity controls, so the same scenes
can be simulated under a counterfactual law (``gravity_off``, ``pass_through``,
``vanish_when_occluded``). Each clip is seeded from ``(seed, clip index)`` alone, so a set is
byte-identical whatever ``jobs`` is, and a counterfactual set shows the same scenes as the ordinary
set of the same seed. Clips stream from ``parallel_map`` (in order) into the shard writer, so
memory does not grow with ``n``.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

from voe.concepts.base import stable_seed
from voe.concepts.generate import manifest_meta
from voe.errors import UnknownNameError, VoeError
from voe.io.probeset import ClipRecord, write_probe_set
from voe.parallel import parallel_map
from voe.sim.rollout import simulate
from voe.sim.scene import Scene, SimConfig
from voe.sim.world import World
from voe.world.sampler import sample_scene

COUNTERFACTUALS = ("none", "gravity_off", "pass_through", "vanish_when_occluded")


def _vanisher(scene: Scene) -> Callable[[World], None]:
    def vanish(world: World) -> None:
        for slot, (lo, hi) in world.bboxes().items():
            if any(o.contains_box(lo, hi) for o in scene.occluders):
                world.remove(slot)  # gone for good
    return vanish


def _pass_through(world: World) -> None:
    """Objects pass through each other and through walls, shelves and ramps; the floor still
    holds them (otherwise everything would fall out of the scene)."""
    for slot in world.bodies():
        world.set_passable(slot, statics=True, objects=True)


def make_clip(index: int, seed: int, cfg: SimConfig, counterfactual: str = "none",
              hidden_p: float = 0.0) -> ClipRecord:
    """Clip number ``index`` of the training set drawn with ``seed`` (``hidden_p``: share of
    scenes with their main event behind a screen, ``sampler.sample_scene``)."""
    import numpy as np

    rng = np.random.default_rng(stable_seed("voe-world", seed, index))
    clip_seed = int(rng.integers(2**31))
    scene, summary = sample_scene(rng, cfg, hidden_p)
    events: dict[int, Callable[[World], None]] = {}
    if counterfactual == "gravity_off":
        scene = replace(scene, gravity=(0.0, 0.0))
    elif counterfactual == "pass_through":
        events[0] = _pass_through
    elif counterfactual == "vanish_when_occluded":
        events = dict.fromkeys(range(cfg.n_frames), _vanisher(scene))
    rec = simulate(scene, cfg, events)
    cid = f"train-{index:06d}"
    row = {
        "clip_id": cid, "concept": "train", "concept_name": "train", "set_id": cid,
        "set_kind": "train", "variant": "train", "role": "train", "onset_frame": -1,
        "seed": clip_seed, "visible_violation": False, "n_distractors": summary["n_distractors"],
        "params": json.dumps({**summary, "counterfactual": counterfactual}, sort_keys=True),
        "geometry": json.dumps(rec.geometry, sort_keys=True),
    }
    return ClipRecord(row, rec.frames, rec.states, rec.present, rec.exists)


def _make(job: tuple[int, int, SimConfig, str, float]) -> ClipRecord:
    index, seed, cfg, cf, hidden_p = job
    try:
        return make_clip(index, seed, cfg, cf, hidden_p)
    except Exception as exc:  # a sampler bug: name the clip so it can be reproduced
        raise VoeError(f"training clip {index} (seed {seed}, {cf}) failed: {exc!r}") from exc


def check_counterfactual(counterfactual: str) -> None:
    """Raise ``UnknownNameError`` (with a did-you-mean) for an unknown counterfactual."""
    if counterfactual not in COUNTERFACTUALS:
        import difflib

        close = difflib.get_close_matches(counterfactual, COUNTERFACTUALS, n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        raise UnknownNameError(f"unknown counterfactual '{counterfactual}'{hint} "
                               f"(known: {', '.join(COUNTERFACTUALS)})")


def generate_world(out: Path, n: int, seed: int, cfg: SimConfig, counterfactual: str = "none",
                   jobs: int = 1, overwrite: bool = False,
                   progress: Callable[[int], None] | None = None, hidden_p: float = 0.0) -> dict[str, Any]:
    """Generate and write ``n`` training clips; returns the manifest (``hidden_events`` recorded
    only when ``hidden_p`` > 0, so default manifests are unchanged)."""
    check_counterfactual(counterfactual)
    if n < 1:
        raise VoeError(f"--n must be at least 1, got {n}")
    if not 0.0 <= hidden_p <= 1.0:
        raise VoeError(f"hidden-event share must be in [0, 1], got {hidden_p}")
    work = ((i, seed, cfg, counterfactual, hidden_p) for i in range(n))
    records = parallel_map(_make, work, jobs, progress)
    extra: dict[str, Any] = {"counterfactual": counterfactual, "n": n}
    if hidden_p > 0:
        extra["hidden_events"] = hidden_p
    meta = manifest_meta("train", [], seed, cfg, extra)
    return write_probe_set(out, records, meta, overwrite=overwrite)
