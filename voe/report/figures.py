"""The report's figures, drawn from stored runs and the tables computed from them.

Why each figure exists:

* the accuracy heatmap answers "which model learned which concept" at a glance;
* the looking-time curves show *when* a model is surprised (a model that learned a concept is
  surprised from the onset on in impossible clips, and not before);
* accuracy by condition shows whether success depends on seeing the violation or on clutter;
* filmstrips with traces let a reader check one matched set with their own eyes.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from voe.report.concepts import concept_name
from voe.scoring.runs import Run

_MARK = {"learned": "\u2713", "not learned": "\u2717", "inconclusive": "?", "confounded": "c"}


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def accuracy_heatmap(summary: pd.DataFrame):
    """Models (rows) x concepts (columns), colour = matched-set accuracy, mark = verdict."""
    plt = _plt()
    models = list(dict.fromkeys(summary["model"]))
    concepts = sorted(summary["concept"].unique())
    acc = summary.pivot(index="model", columns="concept", values="accuracy").reindex(index=models, columns=concepts)
    ver = summary.pivot(index="model", columns="concept", values="verdict").reindex(index=models, columns=concepts)
    fig, ax = plt.subplots(figsize=(1.2 * len(concepts) + 2.8, 0.6 * len(models) + 1.6))
    im = ax.imshow(acc.to_numpy(dtype=float), cmap="RdBu", vmin=0.0, vmax=1.0, aspect="auto")
    for i in range(len(models)):
        for j in range(len(concepts)):
            a = acc.iat[i, j]
            if np.isnan(a):
                continue
            ax.text(j, i, f"{a:.2f} {_MARK.get(ver.iat[i, j], '')}", ha="center", va="center",
                    fontsize=9, color="white" if abs(a - 0.5) > 0.3 else "black")
    ax.set_xticks(range(len(concepts)), [concept_name(c) for c in concepts], rotation=30, ha="right")
    ax.set_yticks(range(len(models)), models)
    cb = fig.colorbar(im, ax=ax, fraction=0.04, pad=0.02)
    cb.set_label("matched-set accuracy (0.5 = chance)")
    ax.set_title("Matched-set accuracy  (\u2713 learned, \u2717 not learned, ? inconclusive)", fontsize=10)
    fig.tight_layout()
    return fig


def aligned_traces(run: Run) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Surprise around the onset, per concept.

    Returns:
        ``by_role``: mean per (concept, role, rel_t) with a 95% band (1.96 SEM over clips);
        ``excess``: mean per (concept, rel_t) of the within-set difference (impossible clips'
        mean minus possible clips' mean), with a 95% band (1.96 SEM over sets). The difference
        removes what a set's clips share (scene, number of objects), which dominates ``by_role``.
    """
    clips = run.clips
    N, T = run.nll.shape
    onset = clips["onset_frame"].to_numpy()
    rel = np.arange(T)[None, :] - onset[:, None]  # (N, T)
    long = pd.DataFrame({"concept": np.repeat(clips["concept"].to_numpy(), T),
                         "set_id": np.repeat(clips["set_id"].to_numpy(), T),
                         "role": np.repeat(clips["role"].to_numpy(), T),
                         "rel_t": rel.reshape(-1), "nll": run.nll.reshape(-1)}).dropna()
    by_role = long.groupby(["concept", "role", "rel_t"])["nll"].agg(["mean", "std", "count"]).reset_index()
    by_role["band"] = 1.96 * by_role["std"].fillna(0.0) / np.sqrt(by_role["count"])
    per_set = long.groupby(["concept", "set_id", "rel_t", "role"])["nll"].mean().unstack("role")
    diff = (per_set.get("impossible") - per_set.get("possible")).dropna().rename("d").reset_index()
    excess = diff.groupby(["concept", "rel_t"])["d"].agg(["mean", "std", "count"]).reset_index()
    excess["band"] = 1.96 * excess["std"].fillna(0.0) / np.sqrt(excess["count"])
    return by_role, excess


def looking_time(run: Run, concepts: Sequence[str]):
    """Per concept: mean surprise of possible vs impossible clips around the onset (top) and the
    within-set excess surprise of the impossible clips (bottom)."""
    plt = _plt()
    by_role, excess = aligned_traces(run)
    n = len(concepts)
    ncol = min(4, n)
    nrow = -(-n // ncol)
    fig, axes = plt.subplots(2 * nrow, ncol, figsize=(3.3 * ncol, 4.2 * nrow + 0.5), squeeze=False,
                             sharex="col", gridspec_kw={"height_ratios": [1.3, 1.0] * nrow})
    for k, concept in enumerate(concepts):
        top, bottom = axes[2 * (k // ncol)][k % ncol], axes[2 * (k // ncol) + 1][k % ncol]
        for role, color in (("possible", "tab:blue"), ("impossible", "tab:red")):
            d = by_role[(by_role["concept"] == concept) & (by_role["role"] == role)]
            top.plot(d["rel_t"], d["mean"], color=color, lw=1.5, label=role)
            top.fill_between(d["rel_t"], d["mean"] - d["band"], d["mean"] + d["band"], color=color,
                             alpha=0.15, lw=0)
        e = excess[excess["concept"] == concept]
        bottom.plot(e["rel_t"], e["mean"], color="black", lw=1.5)
        bottom.fill_between(e["rel_t"], e["mean"] - e["band"], e["mean"] + e["band"], color="gray",
                            alpha=0.3, lw=0)
        bottom.axhline(0, color="gray", lw=0.8)
        for ax in (top, bottom):
            ax.axvline(0, color="black", ls="--", lw=0.8)
            ax.tick_params(labelsize=7)
        top.set_title(concept_name(concept), fontsize=10)
        top.set_ylabel(f"surprise ({run.unit}/frame)", fontsize=8)
        bottom.set_ylabel("impossible − possible", fontsize=8)
        bottom.set_xlabel("frames from onset", fontsize=8)
        if k == 0:
            top.legend(fontsize=7, loc="best")
    for k in range(n, nrow * ncol):
        axes[2 * (k // ncol)][k % ncol].axis("off")
        axes[2 * (k // ncol) + 1][k % ncol].axis("off")
    fig.suptitle(f"{run.label}: surprise around the violation onset (mean and 95% band)", fontsize=10)
    fig.tight_layout()
    return fig


def _level_order(cond: str) -> tuple[int, int, str]:
    """visible, occluded, then distractor counts in numeric order."""
    if cond[:1].isdigit():
        return 1, int(cond.split()[0]), cond
    return 0, {"visible": 0, "occluded": 1}.get(cond, 2), cond


def accuracy_by_condition(conditions: pd.DataFrame):
    """Pooled accuracy per condition (visible/occluded; number of distractors), bars per model."""
    plt = _plt()
    pooled = conditions[conditions["concept"] == "all"]
    models = list(dict.fromkeys(pooled["model"]))
    kinds = [("visibility", "violation visible or occluded"), ("distractors", "number of distractors")]
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.4), gridspec_kw={"width_ratios": [2, 3]})
    width = 0.8 / max(1, len(models))
    cmap = plt.get_cmap("tab10")
    for ax, (kind, title) in zip(axes, kinds, strict=True):
        d = pooled[pooled["condition_kind"] == kind]
        levels = sorted(d["condition"].unique(), key=_level_order)
        for m, model in enumerate(models):
            dm = d[d["model"] == model].set_index("condition").reindex(levels)
            x = np.arange(len(levels)) + (m - (len(models) - 1) / 2) * width
            acc = dm["accuracy"].to_numpy(dtype=float)
            err = np.vstack([acc - dm["ci_low"].to_numpy(dtype=float), dm["ci_high"].to_numpy(dtype=float) - acc])
            ax.bar(x, acc, width, color=cmap(m % 10), label=model, yerr=np.nan_to_num(err),
                   capsize=2, error_kw={"lw": 0.8})
            ax.plot(x, acc, ls="none", marker="_", ms=10 * width / 0.2, mew=2, color="black")  # visible at 0
        ax.axhline(0.5, color="black", ls="--", lw=0.8)
        ax.set_xticks(range(len(levels)), levels, fontsize=8)
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("matched-set accuracy", fontsize=8)
        ax.set_title(title, fontsize=10)
    axes[1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.suptitle("Accuracy by condition, all concepts pooled (bars: 95% bootstrap CI; dashed: chance)",
                 fontsize=10)
    fig.tight_layout()
    return fig


def example_filmstrip(run: Run, frames: np.ndarray, set_id: str):
    """A matched set's clips (frames ``(n, T, H, W)``) with ``run``'s surprise trace under each."""
    from voe.report.filmstrip import filmstrip_figure

    clips = run.clips[run.clips["set_id"] == set_id]
    order = clips.sort_values(["role", "variant"], ascending=[False, True])  # possible first
    idx = [list(clips.index).index(i) for i in order.index]
    labels = [v if v == r else f"{v} ({r})" for v, r in zip(order["variant"], order["role"], strict=True)]
    T = frames.shape[1]
    return filmstrip_figure([frames[i] for i in idx], labels, order["onset_frame"].astype(int).tolist(),
                            every=max(1, T // 14), traces=[run.nll[i] for i in order.index], unit=run.unit,
                            title=f"{set_id}: surprise of {run.label} under each clip "
                                  "(red box / dashed line: onset)")
