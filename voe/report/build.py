"""Build a comparison report (markdown, html, csv, figures) from stored runs.

Why from stored runs only: a report must be reproducible without the models, their weights or a
GPU; the only other input is the probe set each run recorded, read for example frames.
"""

from __future__ import annotations

import os
import re
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from voe.errors import ProbeSetError
from voe.io.atomic import atomic_dir
from voe.io.paths import show_path
from voe.report import render as R
from voe.report.concepts import concept_name, describe
from voe.report.filmstrip import save_figure
from voe.report.training import capped_note, training_text
from voe.scoring.metrics import TIE_RTOL
from voe.scoring.runs import Run, load_runs
from voe.scoring.table import concept_table, condition_table
from voe.scoring.verdict import CONFOUNDED_RULE, HALVES_RULE, RULE

CSV_COLUMNS = ("model", "concept", "n_sets", "accuracy", "ci_low", "ci_high", "p_value", "verdict",
               "p_holm", "note", "relative_surprise", "pair_acc_max", "auroc", "raw_verdict", "confounded_by",
               "halves", "halves_ci_low", "halves_ci_high", "halves_p_holm")


def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-") or "x"


def _example_frames(runs: Sequence[Run], set_ids: Sequence[str],
                    show_paths: bool = False) -> tuple[dict[str, np.ndarray], str]:
    """Frames ``(n_clips, T, H, W)`` per set id, from the probe set recorded in the runs."""
    from voe.io.probeset import load_probe_set

    run = runs[0]
    try:
        ps = load_probe_set(run.probes_path)
        if ps.manifest_sha256 != run.manifest_sha256:
            return {}, (f"the probe set at {show_path(run.probes_path, show_paths)} has changed since scoring "
                        "(manifest hash differs), so example frames are not shown")
        out = {}
        for sid in set_ids:
            ids = run.clips.loc[run.clips["set_id"] == sid, "clip_id"].tolist()
            out[sid] = ps.get(ids)["frames"]
        return out, ""
    except ProbeSetError as exc:
        why = str(exc) if show_paths else f"the probe set {show_path(run.probes_path)} cannot be read"
        return {}, f"example frames are not shown: {why}"


def _publishable(root: Path) -> None:
    """Give the report the usual permissions (temporary files are created owner-only)."""
    mask = os.umask(0)
    os.umask(mask)
    for p in [root, *root.rglob("*")]:
        p.chmod((0o777 if p.is_dir() else 0o666) & ~mask)


def _describe_runs(runs: Sequence[Run]) -> pd.DataFrame:
    rows = []
    for r in runs:
        m = r.meta["model"]
        args = ", ".join(f"{k}={v}" for k, v in sorted((m.get("args") or {}).items()))
        rows.append({"model": r.label, "ref": m.get("ref", ""), "args": args,
                     "observation": m.get("observation", ""), "surprise": r.surprise_kind,
                     "check": r.meta.get("check", "-"),  # check_model before scoring: passed / skipped
                     "checkpoint sha256": (m.get("checkpoint_sha256") or "-")[:12],
                     "training": training_text(m.get("training")),
                     "clips": len(r.clips), "wall time (s)": r.meta.get("wall_time_s", ""),
                     "run": r.path.name})
    return pd.DataFrame(rows)


def build_report(run_dirs: Sequence[str | Path], out: Path, title: str | None = None,
                 n_boot: int = 10_000, seed: int = 0, overwrite: bool = False,
                 validity: Path | None = None, show_paths: bool = False) -> pd.DataFrame:
    """Write ``report.md``, ``report.html``, ``summary.csv``, ``conditions.csv`` and ``figures/``.

    The probe set is named by its folder name and manifest sha256; ``show_paths`` adds its
    absolute path (left out by default: it says nothing to a reader elsewhere).

    Raises:
        RunError: no runs, a malformed or empty run, or runs from different probe sets.

    Returns:
        The summary table (one row per model x concept).
    """
    from voe.controls.check import check_probe_set
    from voe.controls.confound import apply_confounding, scoped_confounders
    from voe.report import figures as F
    from voe.report.validity import control_blocks, summary_sizing

    runs = load_runs(run_dirs)
    check = check_probe_set(runs[0].probes_path, runs[0].manifest_sha256,
                            Path(validity) if validity is not None else None, n_boot=n_boot, runs=runs)
    arch_of = {r.label: str(r.meta["model"].get("class", "")) for r in runs}
    summary = apply_confounding(concept_table(runs, n_boot=n_boot, seed=seed), check.confounds,
                                scoped_confounders(check.matrix) if not check.matrix.empty else {}, arch_of)
    conditions = condition_table(runs, n_boot=n_boot, seed=seed)
    concepts = sorted(summary["concept"].unique())
    title = title or f"voe report: {len(runs)} model(s) x {len(concepts)} concept(s)"
    ref = runs[0]
    out = Path(out)
    with atomic_dir(out, overwrite=overwrite) as tmp:
        (tmp / "figures").mkdir()
        summary[list(CSV_COLUMNS)].to_csv(tmp / "summary.csv", index=False, float_format="%.6g")
        conditions.to_csv(tmp / "conditions.csv", index=False, float_format="%.6g")
        save_figure(F.accuracy_heatmap(summary), tmp / "figures" / "accuracy_heatmap.png")
        save_figure(F.accuracy_by_condition(conditions), tmp / "figures" / "accuracy_by_condition.png")
        looking = []
        for run in runs:
            name = f"figures/looking_time_{_slug(run.label)}.png"
            save_figure(F.looking_time(run, concepts), tmp / name)
            looking.append(R.Figure(name, f"looking time of {run.label}"))
        # One example set per concept (a visible violation if there is one), traced by the model
        # with the best accuracy on that concept.
        examples = {}
        for concept in concepts:
            sets = ref.clips[ref.clips["concept"] == concept].sort_values(
                ["visible_violation", "set_id"], ascending=[False, True])
            best = summary[summary["concept"] == concept].sort_values("accuracy", ascending=False, kind="stable")
            examples[concept] = (str(sets["set_id"].iloc[0]), str(best["model"].iloc[0]))
        frames, film_note = _example_frames(runs, [s for s, _ in examples.values()], show_paths)
        films = []
        by_label = {r.label: r for r in runs}
        for concept, (sid, model) in examples.items():
            if sid in frames:
                name = f"figures/filmstrip_{_slug(concept_name(concept))}.png"
                save_figure(F.example_filmstrip(by_label[model], frames[sid], sid), tmp / name)
                films.append(R.Figure(name, f"filmstrip {sid}", f"{concept}: set {sid}, traces of {model}."))
        blocks = _blocks(title, runs, summary, conditions, concepts, looking, films, film_note, show_paths)
        blocks[-2:-2] = [*control_blocks(check), R.Para(summary_sizing(summary))]
        if validity is not None:
            blocks[-2:-2] = _validity_blocks(Path(validity), tmp, check.confounds)
        check.matrix.to_csv(tmp / "controls.csv", index=False, float_format="%.6g")
        (tmp / "report.md").write_text(R.to_markdown(blocks))
        (tmp / "report.html").write_text(R.to_html(blocks, title, tmp))
        _publishable(tmp)
    return summary


def _validity_blocks(validity: Path, tmp: Path, confounds: pd.DataFrame) -> list[R.Block]:
    """The "Is the suite valid?" section from a ``voe validate-suite`` output directory."""
    import shutil

    from voe.controls.check import read_matrix
    from voe.report.validity import validity_blocks

    matrix, _ = read_matrix(validity)
    shutil.copy(validity / "figures" / "specificity.png", tmp / "figures" / "specificity.png")
    return validity_blocks(matrix, "figures/specificity.png", confounds=confounds)


def _blocks(title, runs, summary, conditions, concepts, looking, films, film_note,
            show_paths: bool = False) -> list[R.Block]:
    ref = runs[0]
    show = summary.copy()
    show["95% CI"] = [f"[{lo:.2f}, {hi:.2f}]" for lo, hi in zip(show["ci_low"], show["ci_high"], strict=True)]
    show["halves"] = [("-" if np.isnan(h) else f"{h:.2f} [{lo:.2f}, {hi:.2f}]") for h, lo, hi in
                      zip(show["halves"], show["halves_ci_low"], show["halves_ci_high"], strict=True)]
    show = show[["model", "concept", "n_sets", "accuracy", "95% CI", "halves", "p_value", "p_holm", "verdict", "note",
                 "confounded_by", "pair_acc_max", "relative_surprise", "auroc"]]
    pooled = conditions[conditions["concept"] == "all"].copy()
    pooled["95% CI"] = [f"[{lo:.2f}, {hi:.2f}]" for lo, hi in zip(pooled["ci_low"], pooled["ci_high"], strict=True)]
    b: list[R.Block] = [
        R.Heading(title, 1),
        R.Para(f"Generated {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} from {len(runs)} stored "
               f"run(s) of the probe set `{show_path(ref.probes_path, show_paths)}` (manifest sha256 "
               f"`{ref.manifest_sha256[:16]}`). Every number below is computed from the per-frame "
               "surprise the runs stored; no model was run to make this report."),
        R.Heading("How to read this report"),
        R.Para("Each probe is a *matched set*: clips that are identical except that some show a physically "
               "impossible event from an *onset* frame on. A model reads every clip frame by frame and "
               "reports its *surprise* (negative log-likelihood of each frame given the past, in nats; "
               "a model may instead declare a *bound* on it or a representation-space prediction *error*, "
               "shown as `surprise` under Models: every accuracy, CI, p-value and AUROC below only "
               "compares surprises and means the same for every kind, while relative surprise needs "
               "nats and is left blank otherwise). "
               "A model that has learned a concept is more surprised by the impossible clips, like an "
               "infant who looks longer at an impossible event (violation of expectation). Quadruplets "
               "are spliced so that the impossible pair holds exactly the frames of the possible pair: "
               "a model that judges single frames cannot beat chance (0.5)."),
        R.Heading("Concepts tested"),
        R.Bullets(tuple(f"**{concept_name(c)}** (`{c}`): {describe(c) or 'no description available.'}"
                        for c in concepts)),
        R.Heading("Models"),
        R.Table(_describe_runs(runs)),
        *([R.Para(note)] if (note := capped_note(runs)) else []),
        R.Heading("Which model learned which concept"),
        R.Figure("figures/accuracy_heatmap.png", "accuracy heatmap",
                 "Rows are models, columns concepts. Colour and number: matched-set accuracy (blue = the "
                 "model is more surprised by impossible events; white = chance, 0.5; red = reversed). "
                 "Mark: the verdict."),
        R.Table(show),
        R.Heading("Metrics and verdict rule", 3),
        R.Bullets((
            "**accuracy** (matched-set, primary): per set 1 if the summed surprise of the impossible clips "
            "exceeds that of the possible clips (quadruplet: S(AB)+S(BA) vs S(A)+S(B); pair: one clip vs "
            f"the other), 0.5 on a tie (relative tolerance {TIE_RTOL:g}), 0 otherwise; averaged over "
            "sets. Frames a model does not score are dropped from all clips of a set.",
            "**95% CI**: percentile bootstrap over matched sets (10,000 resamples, seeded).",
            "**p_value**: one-sided sign-flip permutation test within matched sets (which side is "
            "impossible is swapped at random; exact for up to 16 sets); **p_holm**: Holm-adjusted "
            "across the concepts of each model.",
            "**pair_acc_max**: the same comparison on each clip's peak surprise, over every "
            "(possible, impossible) clip pair of a set.",
            "**relative_surprise**: mean over sets of (S_imp - S_pos) / (S_imp + S_pos).",
            "**auroc**: probability that an impossible clip's total surprise exceeds a possible clip's, "
            "over all clips of the concept regardless of set (ties 0.5); unlike accuracy it is hurt by "
            "clips that are simply harder to predict.",
            "**halves**: on spliced quadruplets, the share of violations (each impossible clip against the "
            "possible clip showing the same frames) that surprise the model, with its 95% CI; - for pairs.",
            "**note**: *chance* when the CI contains 0.5, *reversed* when it lies entirely below 0.5, "
            "*one-sided* when the sum is right but the halves are not (see the rule below).",
        )),
        R.Para("Verdict rule: " + RULE + " " + HALVES_RULE + " " + CONFOUNDED_RULE),
        R.Heading("Looking time: surprise around the onset"),
        R.Para("One figure per model, one column per concept; the x axis is the frame relative to the "
               "violation onset (dashed line). Top: mean surprise per frame of possible (blue) and "
               "impossible (red) clips, with a 95% band (1.96 standard errors over clips); the band is "
               "wide when scenes differ in how hard they are to predict. Bottom: the *excess surprise*, "
               "within each matched set the impossible clips' surprise minus the possible clips', "
               "averaged over sets with a 95% band over sets. A model that has learned the concept shows "
               "an excess near zero before the onset and above zero at or after it (its looking time "
               "goes up). Below zero means the possible events surprise it more."),
        *looking,
        R.Heading("Accuracy by condition"),
        R.Figure("figures/accuracy_by_condition.png", "accuracy by condition",
                 "Left: sets whose violation happens in view vs behind an occluder. Right: sets by number "
                 "of distractor objects. All concepts pooled; error bars are 95% bootstrap CIs; the "
                 "dashed line is chance. A drop when occluded means the model detects visible glitches "
                 "but does not track hidden objects; a drop with distractors means clutter confuses it."),
        R.Table(pooled[["model", "condition_kind", "condition", "n_sets", "accuracy", "95% CI"]]),
        R.Para("Per concept numbers are in `conditions.csv`."),
        R.Heading("Example matched sets"),
        R.Para("One set per concept (a visible violation when there is one). Each row is a clip, frames "
               "left to right, the onset frame outlined in red; under each clip is its per-frame surprise "
               "under the model with the best accuracy on that concept, on one y scale for the whole set. "
               "Expect the impossible clips' traces (red) to rise at or after the onset."),
        *films,
    ]
    if film_note:
        b.append(R.Para(f"*Note:* {film_note}."))
    versions = ref.meta.get("versions", {})
    b += [R.Heading("Provenance"),
          R.Para("Package versions of the first run: "
                 + ", ".join(f"{k} {v}" for k, v in sorted(versions.items()))
                 + ". Each run directory holds its own `run.json`.")]
    return b
