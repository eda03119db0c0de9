"""``validate_suite``: prepare data, run every control, build and write the specificity matrix."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import pandas as pd

from voe.controls.builtin import builtin_controls
from voe.controls.check import enrich_runs
from voe.controls.matrix import specificity_matrix
from voe.controls.probe_runs import probe_set_runs, set_balance
from voe.controls.run import ControlSetup, run_controls
from voe.controls.spec import Control


def default_per_concept(n_concepts: int, n_conditions: int = 2) -> int:
    """Sets per concept so that a perfect score on each condition's share is decisive after Holm
    over a control's ``n_concepts * n_conditions`` condition cells (8 concepts: 18)."""
    from voe.scoring.verdict import min_sets_decisive

    return n_conditions * min_sets_decisive(n_concepts * n_conditions)


def ensure_probes(probes: Path | None, work: Path, per_concept: int | None, seed: int, size: int) -> Path:
    """The given probe set, or a core-suite one generated (once) under ``work``."""
    if probes is not None:
        return Path(probes)
    out = work / "probes"
    if not (out / "manifest.json").exists():
        from voe.concepts.generate import generate_probe_set, resolve_concepts
        from voe.progress import progress
        from voe.sim.scene import SimConfig

        ids = resolve_concepts("core")
        per_concept = per_concept or default_per_concept(len(ids))
        with progress(len(ids) * per_concept, "probe sets", "set") as tick:
            generate_probe_set(out, ids, per_concept, seed, SimConfig(size=size), jobs=2,
                               overwrite=True, progress=tick)
    return out


def ensure_world(world: Path | None, work: Path, n: int, seed: int, size: int) -> Path:
    """The given training set, or an ordinary one generated (once) under ``work``."""
    if world is not None:
        return Path(world)
    out = work / "world"
    if not (out / "manifest.json").exists():
        from voe.progress import progress
        from voe.sim.scene import SimConfig
        from voe.world.generate import generate_world

        with progress(n, "training clips", "clip") as tick:
            generate_world(out, n, seed, SimConfig(size=size), jobs=2, overwrite=True, progress=tick)
    return out


def validate_suite(out: Path, work: Path, probes: Path | None = None, world: Path | None = None,
                   user_controls: Sequence[Control] = (), families: tuple[str, ...] | None = None,
                   per_concept: int | None = None, world_n: int = 600, seed: int = 0, size: int = 64,
                   train_steps: int | None = None, checkpoints: dict[str, str] | None = None,
                   say: Callable[[str], None] = print, jobs: int = 1, show_paths: bool = False) -> pd.DataFrame:
    """Run built-in and user controls on a probe set and write the validity report to ``out``.

    Provenance names the probe set and training world by manifest sha256 and by a path relative to
    ``out`` where one exists; absolute paths only with ``show_paths``.
    """
    from voe.io.probeset import load_probe_set
    from voe.io.provenance import package_versions
    from voe.report.validity import write_validity_report
    from voe.scoring.runs import load_run

    work = Path(work)
    probes = ensure_probes(probes, work, per_concept, seed, size)
    ps = load_probe_set(probes)
    world = ensure_world(world, work, world_n, seed, ps.manifest["frame_size"][0])
    ws = load_probe_set(world)
    if list(ws.manifest["frame_size"]) != list(ps.manifest["frame_size"]):
        from voe.errors import ProbeSetError

        raise ProbeSetError(f"training set {world} has {ws.manifest['frame_size']} px frames but probe set "
                            f"{probes} has {ps.manifest['frame_size']}; generate them at one --size")
    controls = builtin_controls(families) if families else builtin_controls()
    controls = [*controls, *user_controls]
    setup = ControlSetup(world=world, work=work, seed=seed, world_n=world_n, train_steps=train_steps,
                         checkpoints=tuple((checkpoints or {}).items()))
    stats = [c for c in controls if c.model.startswith("stat:")]
    scored = [c for c in controls if not c.model.startswith("stat:")]
    run_dirs = run_controls(scored, probes, setup, say, jobs=jobs)
    by_name = {c.name: load_run(d) for c, d in zip(scored, run_dirs, strict=True)}
    enrich_runs(list(by_name.values()), ps.index)  # runs stored before the index had conditions
    say(f"computing {len(stats)} statistics of the probe set")
    by_name.update({c.name: r for c, r in zip(stats, probe_set_runs(ps, stats), strict=True)})
    runs = [by_name[c.name] for c in controls]
    for r, c in zip(runs, controls, strict=True):
        r.label = c.name
    matrix = specificity_matrix(controls, runs, balance=set_balance(ps))
    from voe.io.paths import relative_ref

    ref = (lambda p: str(Path(p).resolve())) if show_paths else (lambda p: relative_ref(p, out))
    provenance = {"probes": ref(probes), "probes_manifest_sha256": ps.manifest_sha256,
                  "world": ref(world),
                  "world_manifest_sha256": ws.manifest_sha256, "seed": seed,
                  "controls": [c.name for c in controls],
                  "versions": package_versions()}
    from voe.controls.confound import confounders, no_balanced_design

    conf = confounders(matrix, no_balanced_design(ps.index))
    write_validity_report(matrix, out, provenance, confounds=conf)
    return matrix
