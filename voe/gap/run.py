"""One call from files to a finished output directory (what ``voe gap`` runs).

Why: the CLI stays thin and the same function is testable without a terminal.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from voe.gap.finder import GapConfig, GapFinder
from voe.gap.output import provenance, write_json


def diagnose(scene: str | Path, recordings: str | Path, out: str | Path, effects: list[str] | None = None,
             max_effects: int = 3, seed: int = 0, config: GapConfig | None = None, figures: bool = True,
             progress: Callable[[str], None] | None = None, n_jobs: int = 1,
             total: Callable[[int], None] | None = None) -> GapFinder:
    """Run the finder and write ``gap.json`` and ``gap.md`` (with its figures unless ``figures`` is False) into ``out``.

    The directory is written whole (temporary sibling, then rename), so an interrupted run
    leaves no ``gap.json`` without its figures. Inputs are named by a path relative to ``out``.
    """
    from voe.io.atomic import atomic_dir
    from voe.io.outputs import check_output
    from voe.io.paths import relative_ref

    check_output(out, "dir", replaces=("gap.json",))  # never replace a folder that is not ours
    finder = GapFinder(effects=effects, max_effects=max_effects, seed=seed, config=config, n_jobs=n_jobs)
    finder.fit(scene, recordings, progress=progress, total=total)
    out = Path(out)
    payload = finder.to_dict()
    inputs = {"scene": scene, "recordings": recordings}
    payload["provenance"] = provenance(seed, inputs, finder.config)
    for key, path in inputs.items():
        payload["provenance"]["inputs"][key]["path"] = relative_ref(path, out)
    with atomic_dir(out, overwrite=True) as tmp:
        write_json(tmp / "gap.json", payload)
        from voe.gap.report import write_report

        write_report(finder, tmp, figures_too=figures)  # gap.md always; figures only if asked
    return finder
