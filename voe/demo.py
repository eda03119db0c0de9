"""``voe demo``: probes -> training worlds -> trained models -> scored runs -> comparison report.

Why one function: it is the main job a newcomer runs, so every step is visible here in order,
sized for 2 CPU cores and about 15 minutes. Training runs two models at a time (one torch thread
each), which is what two cores do best. Every artefact stays in ``work`` so reruns reuse it;
the report goes to ``out``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class DemoConfig:
    """Sizes and CPU budgets of the demo (defaults fit 2 cores in about 15 minutes)."""

    per_concept: int = 20
    world_n: int = 2000
    cf_world_n: int = 2000
    calib_n: int = 200
    size: int = 64
    seed: int = 0
    #: optimiser steps per model: the same seed gives the same checkpoints on any machine (about
    #: 6 min of training on 2 idle cores); ``minutes_cap`` only stops a run on a very slow machine
    steps: dict[str, int] = field(default_factory=lambda: {
        "interaction": 700, "pixel": 400, "mlp": 1500,
        "cf-gravity_off": 400, "cf-pass_through": 400})
    minutes_cap: float = 20.0
    validity: bool = True
    jobs: int = 2


def _train_job(job: tuple[str, str, str, int, float, int, dict[str, Any]]) -> dict[str, Any]:
    """Run in a worker process: train one model and return its checkpoint meta."""
    model, data, out, steps, cap, seed, args = job
    from voe.models.train import TrainConfig, train

    return train(model, Path(data), Path(out), TrainConfig(steps=steps, minutes=cap, seed=seed, threads=1), args)


def reusable(ckpt: Path, say: Callable[[str], None] = print) -> bool:
    """Whether a checkpoint left in the scratch directory by an earlier run can be reused.

    Why: the scratch directory is reused by presence, and a run on a loaded machine once stopped
    ``interaction`` at the safety cap (478 of 700 steps); every rerun then reported that
    under-trained model as the demo's. A checkpoint that records ``time_capped`` is trained again
    (``save_checkpoint`` replaces it atomically, so it stays until the new one is complete).
    """
    if not ckpt.exists():
        return False
    from voe.models.checkpoint import read_checkpoint

    meta = read_checkpoint(ckpt)
    if meta.get("time_capped"):
        say(f"  {ckpt.name}: the stored checkpoint stopped at the time cap after {meta.get('steps')} of "
            f"{meta.get('steps_budget')} steps; training it again")
        return False
    return True


def run_demo(out: Path, work: Path, cfg: DemoConfig, say: Callable[[str], None] = print) -> dict[str, Any]:
    """Run the whole pipeline; returns timings (seconds) per stage."""
    from voe.concepts.generate import generate_probe_set, resolve_concepts
    from voe.parallel import parallel_map
    from voe.progress import progress
    from voe.sim.scene import SimConfig
    from voe.world.generate import generate_world

    work = Path(work)
    work.mkdir(parents=True, exist_ok=True)
    sim = SimConfig(size=cfg.size)
    times: dict[str, float] = {}
    t0 = time.monotonic()

    # 1. data: probes, an ordinary training world, a small calibration world, counterfactual worlds
    probes, world, calib = work / "probes", work / "world", work / "calib"
    ids = resolve_concepts("core")
    if not (probes / "manifest.json").exists():
        with progress(len(ids) * cfg.per_concept, "probe sets", "set") as tick:
            generate_probe_set(probes, ids, cfg.per_concept, cfg.seed, sim, cfg.jobs, True, tick)
    worlds = {"none": (world, cfg.world_n), "calib": (calib, cfg.calib_n)}
    if cfg.validity:
        for cf in ("gravity_off", "pass_through"):
            worlds[cf] = (work / f"world-{cf}", cfg.cf_world_n)
    for cf, (path, n) in worlds.items():
        if not (path / "manifest.json").exists():
            with progress(n, f"training clips ({cf})", "clip") as tick:
                seed = cfg.seed + (1 if cf == "calib" else 0)
                generate_world(path, n, seed, sim, "none" if cf == "calib" else cf, cfg.jobs, True, tick)
    times["data"] = time.monotonic() - t0

    # 2. training: learned models (and counterfactual ones for the validity section), 2 at a time
    t1 = time.monotonic()
    ckpt = work / "checkpoints"
    jobs = [(m, str(world), str(ckpt / m), cfg.steps[m], cfg.minutes_cap, cfg.seed, {})
            for m in ("interaction", "pixel", "mlp")]
    if cfg.validity:
        jobs += [("interaction", str(worlds[cf][0]), str(ckpt / f"interaction-{cf}"),
                  cfg.steps[f"cf-{cf}"], cfg.minutes_cap, cfg.seed, {}) for cf in ("gravity_off", "pass_through")]
    jobs = [j for j in jobs if not reusable(Path(j[2]), say)]  # checkpoints are written atomically
    if jobs:
        say(f"training {len(jobs)} model(s), {cfg.jobs} at a time ({', '.join(f'{Path(j[2]).name} {j[3]}' for j in jobs)} steps)")
        for job, meta in zip(jobs, parallel_map(_train_job, jobs, cfg.jobs, ahead=len(jobs)), strict=True):
            capped = f" (stopped by the {cfg.minutes_cap:g}-min cap)" if meta.get("time_capped") else ""
            say(f"  {Path(job[2]).name}: {meta['steps']} steps{capped}, validation NLL {meta['val_nll']:.2f} nats/frame")
    times["training"] = time.monotonic() - t1

    # 3. scoring: references (calibrated on the calibration world), learned, untrained
    t2 = time.monotonic()
    from voe.io.probeset import load_probe_set
    from voe.models.loading import load_model
    from voe.models.train import TrainConfig, train
    from voe.scoring.score import score_probe_set

    ps = load_probe_set(probes)

    for ref in ("framecopy", "constvel", "oracle"):
        if not (ckpt / ref).exists():
            train(ref, calib, ckpt / ref, TrainConfig(seed=cfg.seed))
    models: list[tuple[str, str, dict[str, Any], Path | None]] = [
        ("framecopy", "framecopy", {}, ckpt / "framecopy"),
        ("constvel", "constvel", {}, ckpt / "constvel"),
        ("oracle", "oracle", {}, ckpt / "oracle"),
        ("mlp", "mlp", {}, ckpt / "mlp"),
        ("pixel", "pixel", {}, ckpt / "pixel"),
        ("interaction", "interaction", {}, ckpt / "interaction"),
        ("interaction-untrained", "interaction", {"seed": 1}, None),
    ]
    run_dirs = []
    for label, ref, args, ck in models:
        rd = work / "runs" / label
        run_dirs.append(rd)
        if (rd / "run.json").exists():
            continue
        model = load_model(ref, args or None, ck)
        model.name = label
        with progress(len(ps), f"scoring {label}", "clip") as tick:
            score_probe_set(model, ps, rd, model_ref=ref, model_args=args, checkpoint=ck,
                            batch_size=32, overwrite=True, progress=tick)
    times["scoring"] = time.monotonic() - t2

    # 4. validity controls (issue: "Is the suite valid?") and the report
    t3 = time.monotonic()
    validity = None
    if cfg.validity:
        from voe.controls.suite import validate_suite

        validity = out.parent / f"{out.name}-validity"
        validate_suite(validity, work / "validity", probes=probes, world=calib, seed=cfg.seed,
                       checkpoints={cf: str(ckpt / f"interaction-{cf}") for cf in ("gravity_off", "pass_through")},
                       say=say, jobs=cfg.jobs)
    times["validity"] = time.monotonic() - t3
    from voe.report.build import build_report

    build_report(run_dirs, out, title="voe demo: which concepts has each model learned?",
                 overwrite=True, validity=validity)
    times["total"] = time.monotonic() - t0
    return times
