"""The "Is the suite valid?" report: the specificity matrix as a figure, tables and a reading.

Why: a reader should see at a glance that models which know a law pass its probe, that models
deprived of exactly that law fail it, and that nothing else moves; and every cell where this
does not hold must stand out. Built from ``matrix.csv`` only (never re-runs a control).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from voe.io import jsonio
from voe.report import render as R
from voe.report.concepts import concept_name
from voe.scoring.verdict import CONFOUNDED_RULE

_EXPECT_MARK = {"pass": "P", "fail": "F", "chance": "C", "not-learned": "N", "none": "-"}


def matrix_figure(matrix: pd.DataFrame):
    """Controls (rows) x concepts (columns): colour = accuracy; text = accuracy and the declared
    expectation (P pass, F fail, C chance, - none); a thick red frame marks a cell that does not
    behave as declared."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    m = matrix[matrix["condition"] == "all"]
    controls = list(dict.fromkeys(m["control"]))
    concepts = sorted(m["concept"].unique())
    acc = m.pivot(index="control", columns="concept", values="accuracy").reindex(index=controls, columns=concepts)
    exp = m.pivot(index="control", columns="concept", values="expected").reindex(index=controls, columns=concepts)
    ok = m.pivot(index="control", columns="concept", values="as_declared").reindex(index=controls, columns=concepts)
    cond_bad = matrix[(matrix["condition"] != "all") & matrix["as_declared"].eq(False)]
    fig, ax = plt.subplots(figsize=(1.15 * len(concepts) + 3.5, 0.42 * len(controls) + 1.8))
    im = ax.imshow(acc.to_numpy(dtype=float), cmap="RdBu", vmin=0, vmax=1, aspect="auto")
    for i, c in enumerate(controls):
        for j, k in enumerate(concepts):
            a = acc.iat[i, j]
            if np.isnan(a):
                continue
            ax.text(j, i, f"{a:.2f} {_EXPECT_MARK.get(exp.iat[i, j], '?')}", ha="center", va="center",
                    fontsize=7.5, color="white" if abs(a - 0.5) > 0.3 else "black")
            bad = ok.iat[i, j] is False or ((cond_bad["control"] == c) & (cond_bad["concept"] == k)).any()
            if bad:
                ax.add_patch(Rectangle((j - 0.48, i - 0.46), 0.96, 0.92, fill=False, ec="#d00000", lw=2.5))
    ax.set_xticks(range(len(concepts)), [concept_name(c) for c in concepts], rotation=30, ha="right")
    ax.set_yticks(range(len(controls)), controls, fontsize=8)
    cb = fig.colorbar(im, ax=ax, fraction=0.035, pad=0.02)
    cb.set_label("matched-set accuracy")
    ax.set_title("Specificity matrix: accuracy and declaration (P pass, F fail, C chance, N not learned); "
                 "red frame = not as declared", fontsize=9)
    fig.tight_layout()
    return fig


def _count(cells: pd.DataFrame) -> str:
    ok = int(cells["as_declared"].astype(bool).sum())
    return f"{ok} of {len(cells)}"


def reading(matrix: pd.DataFrame) -> str:
    """A one-paragraph reading of the matrix, computed from it: cells that could have failed and
    cells that could not (fixed by construction) are counted apart."""
    declared = matrix[matrix["as_declared"].notna()]
    live = declared[declared["could_fail"].astype(bool)]
    fixed = declared[~declared["could_fail"].astype(bool)]
    parts = [f"{_count(live)} declared cells that could have failed behave as declared"]
    for fam, g in live.groupby("family", sort=True):
        parts.append(f"{fam}: {_count(g)}")
    text = "; ".join(parts) + ". "
    if not fixed.empty:
        text += (f"A further {len(fixed)} cells could not have failed (a control that ties by "
                 "construction on a balance every set of the cell reaches, or a constant): "
                 f"{_count(fixed)} as declared; they check the construction and are not evidence. ")
    bad = live[~live["as_declared"].astype(bool)]
    if bad.empty:
        text += ("Every control that could have failed behaves as declared: lesions break exactly "
                 "what they declare, knowledge-free controls sit at chance and physics-poor "
                 "references learn nothing beyond their knowledge.")
    else:
        cells = ", ".join(f"{r.control} x {concept_name(r.concept)}"
                          + (f" ({r.condition})" if r.condition != "all" else "")
                          + f" (expected {r.expected}, got {r.verdict}, accuracy {r.accuracy:.2f})"
                          for r in bad.itertuples())
        text += (f"Cells that do not behave as declared: {cells}. A knowledge-free or physics-poor "
                 "control off its declaration means the probe gives its answer away (the concept is "
                 "marked confounded in reports); a lesion that fails to break its own concept means "
                 "the probe can be solved without that law; one that breaks another concept means "
                 "that probe also depends on the lesioned law.")
    return text


def sizing(matrix: pd.DataFrame) -> str:
    """How many sets a perfect score needs to be decisive here, and how many each cell has."""
    from voe.scoring.verdict import min_sets_decisive

    cond = matrix[matrix["condition"] != "all"]
    m_all = int(matrix[matrix["condition"] == "all"].groupby("control").size().max())
    n_all = min_sets_decisive(m_all)
    text = (f"With {m_all} concept cells per control (Holm), a perfect score is decisive from "
            f"{n_all} sets per concept; the smallest concept here has "
            f"{int(matrix.loc[matrix['condition'] == 'all', 'n_sets'].min())}.")
    if not cond.empty:
        m_c = int(cond.groupby("control").size().max())
        n_c = min_sets_decisive(m_c)
        have = int(cond["n_sets"].min())
        text += (f" With {m_c} condition cells per control, a perfect score on one condition is "
                 f"decisive from {n_c} sets per condition; the smallest condition here has {have}"
                 + (" (too few: such a cell cannot come out learned)." if have < n_c else "."))
    return text


def validity_blocks(matrix: pd.DataFrame, figure_path: str, level: int = 2,
                    confounds: pd.DataFrame | None = None) -> list[R.Block]:
    """Report blocks: heading, explanation, figure, reading, sizing, confounds, mismatches, matrix."""
    bad = matrix[matrix["as_declared"].eq(False)]
    show = matrix[matrix["condition"] == "all"].copy()
    cond = matrix[(matrix["condition"] != "all") & (matrix["expected"] != "none")]
    cols = ["control", "concept", "condition", "n_sets", "accuracy", "ci_low", "ci_high", "verdict",
            "expected", "as_declared", "could_fail"]
    blocks: list[R.Block] = [
        R.Heading("Is the suite valid?", level),
        R.Para("Controls are models or statistics whose knowledge is declared in code before they "
               "run, scored exactly like any model. *Knowledge-free* controls (a per-frame density, "
               "motion energy, object height and speed, and a stress-test classifier of single "
               "frames or single steps, cross-validated over matched sets) and *random networks* "
               "(every learned architecture with random, non-zero weights, several seeds) know "
               "nothing and must sit at chance, in either direction. *Physics-poor* references (frame "
               "copy, constant velocity, track smoothness) must pass what their knowledge implies and "
               "learn nothing else. *Lesioned oracles* are the physics oracle with one law knocked "
               "out, each declaring for every concept what it must break. *Counterfactual* controls "
               "are the object-centric model trained in a world without a law."),
        R.Figure(figure_path, "specificity matrix",
                 "Rows: controls; columns: concepts. Colour and number: matched-set accuracy; letter: "
                 "what the control declares (P should pass = learned, F should fail = not learned, "
                 "C chance = 95% CI contains 0.5, N not learned, - nothing declared). A red frame marks "
                 "a cell (or one of its conditions) whose outcome differs from the declaration."),
        R.Para("**Reading.** " + reading(matrix)),
        R.Para("**Size.** " + sizing(matrix)),
    ]
    if confounds is not None and confounds["confounded"].any():
        blocks += [R.Para("Concepts and conditions where a control shows the probe cannot tell "
                          "(every model's verdict there is *confounded*):"),
                   R.Table(confounds[confounds["confounded"]])]
    if not cond.empty:
        blocks += [R.Para("Declarations about one condition:"), R.Table(cond[cols])]
    if not bad.empty:
        blocks += [R.Para("Cells that differ from their declaration:"), R.Table(bad[cols])]
    blocks += [R.Para("The full matrix with confidence intervals and verdicts:"),
               R.Table(show[["control", "family", "concept", "n_sets", "accuracy", "ci_low", "ci_high",
                             "verdict", "expected", "as_declared", "could_fail"]])]
    return blocks


def control_blocks(check) -> list[R.Block]:
    """Which concepts the probe set cannot decide, and the controls next to the verdicts."""
    b: list[R.Block] = [R.Heading("Can the probes tell? Controls on this probe set"),
                        R.Para(check.note + " " + CONFOUNDED_RULE)]
    conf = check.confounds
    if conf.empty or not conf["confounded"].any():
        b.append(R.Para("No control separates the clips of any concept beyond chance or beyond its "
                        "declared knowledge: every verdict above stands." if not conf.empty else
                        "*Not checked.*"))
    else:
        b += [R.Para("Confounded concepts and conditions, with the controls that confound them "
                     "(accuracy and 95% CI):"), R.Table(conf[conf["confounded"]])]
    m = check.matrix
    if not m.empty:
        pivot = m[m["condition"] == "all"].pivot(index="control", columns="concept", values="accuracy")
        b += [R.Para("Matched-set accuracy of each control on each concept (verdict-carrying sets; "
                     "0.5 is chance, either direction away from it is a giveaway; all cells in "
                     "`controls.csv`):"), R.Table(pivot.reset_index().round(2))]
    return b


def summary_sizing(summary: pd.DataFrame) -> str:
    """How many verdict sets a perfect score needs here (Holm over a model's concepts)."""
    from voe.scoring.verdict import min_sets_decisive

    m = int(summary.groupby("model").size().max())
    need, have = min_sets_decisive(m), int(summary["n_sets"].min())
    return (f"**Size.** With {m} concepts per model (Holm), a perfect score is decisive from {need} "
            f"verdict-carrying sets per concept; the smallest concept here has {have}"
            + (": too few for any verdict there to come out *learned*." if have < need else "."))


def write_validity_report(matrix: pd.DataFrame, out: Path, provenance: dict, overwrite: bool = True,
                          confounds: pd.DataFrame | None = None) -> None:
    """Write ``matrix.csv``, ``confounds.csv``, ``validity.md``, ``validity.html``,
    ``figures/specificity.png``."""

    from voe.io.atomic import atomic_dir
    from voe.report.filmstrip import save_figure

    with atomic_dir(Path(out), overwrite=overwrite) as tmp:
        (tmp / "figures").mkdir()
        matrix.to_csv(tmp / "matrix.csv", index=False, float_format="%.6g")
        if confounds is not None:
            confounds.to_csv(tmp / "confounds.csv", index=False)
        save_figure(matrix_figure(matrix), tmp / "figures" / "specificity.png")
        blocks = [R.Heading("voe validity controls", 1), *validity_blocks(matrix, "figures/specificity.png", confounds=confounds)]
        blocks.append(R.Para("Provenance: " + ", ".join(f"{k}: `{v}`" for k, v in provenance.items())))
        (tmp / "validity.md").write_text(R.to_markdown(blocks))
        (tmp / "validity.html").write_text(R.to_html(blocks, "voe validity controls", tmp))
        (tmp / "provenance.json").write_text(jsonio.dumps(provenance, indent=1, sort_keys=True) + "\n")
