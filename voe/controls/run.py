"""Run validity controls over a probe set: build or train each control, score it, keep the run.

Why: the specificity matrix is built from stored runs, like any report, so every control is
scored through the same ``score_probe_set`` as a user's model. This module only decides how each
control's model is obtained:

* random networks: ``voe.controls.random_nets.random_network`` (no checkpoint);
* statistics of the probe set (``stat:NAME``): not scored here but computed from the stored
  bytes (``voe.controls.probe_runs``), and refused by this module;
* lesioned and intact oracles: calibrated on the training world (``voe train`` does this);
* counterfactual controls: the object-centric model trained on a counterfactual world;
* user controls: ``load_model(ref, args, checkpoint)``.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from voe.controls.spec import Control
from voe.errors import VoeError


@dataclass(frozen=True)
class ControlSetup:
    """Where training data lives and how long counterfactual models train.

    Attributes:
        world: the ordinary training set (calibration of oracles, frame densities).
        work: a scratch directory for checkpoints, counterfactual worlds and runs.
        seed: seed for world generation and training.
        world_n: clips per counterfactual world (same scenes as ``world``'s seed).
        train_steps: optimiser steps per counterfactual model (``None``: the model's preset).
        checkpoints: counterfactual name -> an existing checkpoint to reuse instead of training.
    """

    world: Path
    work: Path
    seed: int = 0
    world_n: int = 600
    train_steps: int | None = None
    model_args: tuple[tuple[str, Any], ...] = ()
    checkpoints: tuple[tuple[str, str], ...] = ()


def _calibrated(ctrl: Control, setup: ControlSetup, say: Callable[[str], None]) -> Any:
    from voe.models.loading import load_model
    from voe.models.train import TrainConfig, train

    ckpt = setup.work / "checkpoints" / ctrl.name
    if not ckpt.exists():  # checkpoints are written atomically: present means complete
        say(f"calibrating {ctrl.name} on {setup.world}")
        train(ctrl.model, setup.world, ckpt, TrainConfig(seed=setup.seed), dict(ctrl.args))
    return load_model(ctrl.model, None, ckpt), ckpt


def _counterfactual(ctrl: Control, setup: ControlSetup, say: Callable[[str], None]) -> Any:
    from voe.models.loading import load_model
    from voe.models.train import TrainConfig, train
    from voe.sim.scene import SimConfig
    from voe.world.generate import generate_world

    reuse = dict(setup.checkpoints).get(ctrl.train_on or "")
    if reuse:
        return load_model(ctrl.model, None, Path(reuse)), Path(reuse)
    world = setup.work / f"world-{ctrl.train_on}"
    if not world.exists():
        from voe.io.probeset import load_probe_set

        size = load_probe_set(setup.world).manifest["frame_size"][0]
        say(f"generating {setup.world_n} {ctrl.train_on} training clips")
        generate_world(world, setup.world_n, setup.seed, SimConfig(size=size), ctrl.train_on, jobs=2)
    ckpt = setup.work / "checkpoints" / ctrl.name
    if not ckpt.exists():
        say(f"training {ctrl.model} on the {ctrl.train_on} world ({setup.train_steps or 'preset'} steps)")
        train(ctrl.model, world, ckpt, TrainConfig(steps=setup.train_steps, seed=setup.seed),
              dict(setup.model_args))
    return load_model(ctrl.model, None, ckpt), ckpt


def build_control(ctrl: Control, setup: ControlSetup, say: Callable[[str], None] = print) -> tuple[Any, Path | None]:
    """The model of a control, and the checkpoint it came from (if any)."""
    from voe.models.loading import load_model

    if ctrl.model.startswith("stat:"):
        raise VoeError(f"control '{ctrl.name}' is a statistic of the probe set ({ctrl.model}), not a "
                       "model; compute it with voe.controls.probe_runs.probe_set_runs")
    if ctrl.family == "counterfactual":
        return _counterfactual(ctrl, setup, say)
    if ctrl.calibrate:
        return _calibrated(ctrl, setup, say)
    ckpt = Path(ctrl.checkpoint) if ctrl.checkpoint else None
    return load_model(ctrl.model, dict(ctrl.args), ckpt), ckpt


def _quiet(_: str) -> None:
    """``say`` of worker processes: their progress is the parent's bar over controls."""


def _score_control(job: tuple[Control, Any, ControlSetup, Path], say: Callable[[str], None] = _quiet,
                   tick: Callable[[int], None] | None = None, single_thread: bool = True) -> str:
    """Build one control and score it on ``job``'s probes (a probe set or its path); returns its
    name. The unit of work of ``run_controls``, in a worker process or in the parent."""
    import sys

    from voe.scoring.score import score_probe_set

    ctrl, probes, setup, out = job
    model, ckpt = build_control(ctrl, setup, say)
    if single_thread and "torch" in sys.modules:  # two workers share two cores
        sys.modules["torch"].set_num_threads(1)
    model.name = ctrl.name  # the matrix row label
    score_probe_set(model, probes, out, model_ref=ctrl.model, model_args=dict(ctrl.args),
                    checkpoint=ckpt, batch_size=32, overwrite=True, progress=tick)
    return ctrl.name


def stale_reason(meta: dict, ctrl: Control, manifest_sha256: str) -> str:
    """Why a stored control run may not stand for ``ctrl`` on this probe set ('' if it may).

    Why more than the probe set: a control is named, not versioned, so a stored
    ``random-interaction-s2`` made by an older architecture (or older scoring code) would
    otherwise keep standing in for today's, and random networks confound only models of their
    own class (``voe.controls.confound``): a stale one silently drops those confounds.
    """
    from voe.scoring.cache import class_code_sha256

    model = meta.get("model", {})
    if meta.get("probes", {}).get("manifest_sha256") != manifest_sha256:
        return "scored another probe set"
    if model.get("ref") != ctrl.model or json.dumps(model.get("args", {}), sort_keys=True, default=str) \
            != json.dumps(dict(ctrl.args), sort_keys=True, default=str):
        return f"was made by {model.get('ref')} {model.get('args')}, not {ctrl.model} {dict(ctrl.args)}"
    try:
        from voe.registry import load_ref

        want = class_code_sha256(load_ref(str(model["class"])))
    except (VoeError, ImportError, KeyError, TypeError, OSError):  # no key today: do not trust it
        want = None
    if not model.get("code_sha256") or model.get("code_sha256") != want:
        return "was computed by other code (code fingerprint differs)"
    return ""


def run_controls(controls: Sequence[Control], probes: Path, setup: ControlSetup,
                 say: Callable[[str], None] = print, reuse: bool = True, jobs: int = 1) -> list[Path]:
    """Score every control on ``probes``; returns the run directories (one per control).

    With ``jobs`` > 1 the controls are built and scored in that many processes (each control's
    run is independent), with one progress bar over controls instead of one per control.
    """
    from voe.io.probeset import load_probe_set
    from voe.parallel import parallel_map
    from voe.progress import progress

    ps = load_probe_set(probes)
    names = [c.name for c in controls]
    if len(set(names)) != len(names):
        raise VoeError(f"control names must be unique, got duplicates in {names}")
    runs = [setup.work / "runs" / c.name for c in controls]
    todo = []
    for ctrl, out in zip(controls, runs, strict=True):
        if reuse and (out / "run.json").exists():
            stale = stale_reason(json.loads((out / "run.json").read_text()), ctrl, ps.manifest_sha256)
            if not stale:
                say(f"reusing the stored run of {ctrl.name}")
                continue
            say(f"scoring {ctrl.name} again: its stored run {stale}")
        todo.append((ctrl, Path(probes), setup, out))
    if jobs > 1 and len(todo) > 1:
        with progress(len(todo), f"controls ({jobs} at a time)", "control") as tick:
            # spawn, not fork: a forked worker inherits locks held by the parent's threads (torch's
            # pool after the parent scored a model, a progress bar) and can wait on them forever
            for name in parallel_map(_score_control, todo, jobs, tick, ahead=len(todo),
                                     start_method="spawn"):
                say(f"scored {name}")
        return runs
    for ctrl, _, _, out in todo:
        with progress(len(ps), f"scoring {ctrl.name}", "clip") as tick:
            _score_control((ctrl, ps, setup, out), say, tick, single_thread=False)
    return runs
