"""The "Is the suite valid?" report: the specificity matrix as a figure, tables and a reading.

Why: a reader should see at a glance that models which know a law pass its probe, that models
deprived of exactly that law fail it, and that nothing else moves; and every cell where this
does not hold must stand out. Built from ``matrix.csv`` only (never re-runs a control).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from voe.report import render as R
from voe.report.concepts import concept_name

_EXPECT_MARK = {"pass": "P", "fail": "F", "chance": "C", "none": "-"}


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
    ax.set_title("Specificity matrix: accuracy and declaration (P pass, F fail, C chance); "
                 "red frame = not as declared", fontsize=9)
    fig.tight_layout()
    return fig


def reading(matrix: pd.DataFrame) -> str:
    """A one-paragraph reading of the matrix, computed from it."""
    m = matrix
    declared = m[m["as_declared"].notna()]
    n_ok = int(declared["as_declared"].astype(bool).sum())
    bad = declared[~declared["as_declared"].astype(bool)]
    fams = {}
    for fam, g in declared.groupby("family"):
        fams[fam] = (int(g["as_declared"].astype(bool).sum()), len(g))
    parts = [f"{n_ok} of {len(declared)} declared cells behave as declared"]
    for fam, (k, n) in sorted(fams.items()):
        parts.append(f"{fam}: {k}/{n}")
    text = "; ".join(parts) + ". "
    if bad.empty:
        text += ("Every lesion breaks exactly the concepts it declares and leaves the others learned, "
                 "every untrained network and frame-only scorer sits at chance where declared, so each "
                 "probe responds to the law it names and to nothing else we tested.")
    else:
        cells = ", ".join(f"{r.control} x {concept_name(r.concept)}"
                          + (f" ({r.condition})" if r.condition != "all" else "")
                          + f" (expected {r.expected}, got {r.verdict}, accuracy {r.accuracy:.2f})"
                          for r in bad.itertuples())
        text += (f"Cells that do not behave as declared: {cells}. Each is a probe (or a declaration) "
                 "to examine: a lesion that fails to break its own concept means the probe can be "
                 "solved without that law; one that breaks another concept means that probe also "
                 "depends on the lesioned law.")
    fo = m[(m["family"] == "frame-only") & (m["condition"] == "all") & (m["expected"] == "none")]
    if not fo.empty:  # pair concepts: frame balance is not guaranteed there, so report the numbers
        best = fo.loc[fo.groupby("concept")["accuracy"].idxmax()]
        text += (" On the pair-fallback concepts, where no splice balances the frames, the best "
                 "frame-only scorer reaches " + ", ".join(f"{r.accuracy:.2f} on {concept_name(r.concept)} "
                                                          f"({r.control})" for r in best.itertuples())
                 + ": what a single frame gives away there.")
    return text


def validity_blocks(matrix: pd.DataFrame, figure_path: str, level: int = 2) -> list[R.Block]:
    """Report blocks: heading, explanation, figure, reading, mismatch table."""
    bad = matrix[matrix["as_declared"].eq(False)]
    show = matrix[matrix["condition"] == "all"].copy()
    cond = matrix[(matrix["condition"] != "all") & (matrix["expected"] != "none")]
    cols = ["control", "concept", "condition", "n_sets", "accuracy", "ci_low", "ci_high", "verdict",
            "expected", "as_declared"]
    blocks: list[R.Block] = [
        R.Heading("Is the suite valid?", level),
        R.Para("Controls are models whose knowledge is known in advance, scored exactly like any "
               "model. *Untrained* networks (3 random initialisations of each learned architecture) "
               "know nothing and must sit at chance. *Frame-only* scorers see one frame at a time; on "
               "spliced quadruplets they must tie exactly (accuracy 0.5), which proves frame balance "
               "empirically. *Lesioned oracles* are the physics oracle with one law knocked out; each "
               "declares which concepts it should break, and must pass the rest. *Counterfactual* "
               "controls are the object-centric model trained in a world without a law."),
        R.Figure(figure_path, "specificity matrix",
                 "Rows: controls; columns: concepts. Colour and number: matched-set accuracy; letter: "
                 "what the control declares (P should pass = learned, F should fail = not learned, "
                 "C chance = 95% CI contains 0.5, - nothing declared). A red frame marks a cell (or one "
                 "of its visible/occluded halves) whose outcome differs from the declaration."),
        R.Para("**Reading.** " + reading(matrix)),
    ]
    if not cond.empty:
        blocks += [R.Para("Declarations about one condition (visible or occluded violations only):"),
                   R.Table(cond[cols])]
    if not bad.empty:
        blocks += [R.Para("Cells that differ from their declaration:"), R.Table(bad[cols])]
    blocks += [R.Para("The full matrix with confidence intervals and verdicts:"),
               R.Table(show[["control", "family", "concept", "n_sets", "accuracy", "ci_low", "ci_high",
                             "verdict", "expected", "as_declared"]])]
    return blocks


def write_validity_report(matrix: pd.DataFrame, out: Path, provenance: dict, overwrite: bool = True) -> None:
    """Write ``matrix.csv``, ``validity.md``, ``validity.html``, ``figures/specificity.png``."""
    import json

    from voe.io.atomic import atomic_dir
    from voe.report.filmstrip import save_figure

    with atomic_dir(Path(out), overwrite=overwrite) as tmp:
        (tmp / "figures").mkdir()
        matrix.to_csv(tmp / "matrix.csv", index=False, float_format="%.6g")
        save_figure(matrix_figure(matrix), tmp / "figures" / "specificity.png")
        blocks = [R.Heading("voe validity controls", 1), *validity_blocks(matrix, "figures/specificity.png")]
        blocks.append(R.Para("Provenance: " + ", ".join(f"{k}: `{v}`" for k, v in provenance.items())))
        (tmp / "validity.md").write_text(R.to_markdown(blocks))
        (tmp / "validity.html").write_text(R.to_html(blocks, "voe validity controls", tmp))
        (tmp / "provenance.json").write_text(json.dumps(provenance, indent=1, sort_keys=True) + "\n")
