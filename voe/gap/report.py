"""Write ``gap.md`` and its figures from a fitted ``GapFinder``.

Why: a reader should see the mismatch, not only read about it. Two figures: recorded versus
simulated trajectories (nominal and with the fitted effects) on a held-out episode, and the
nominal residual over time with the located stretches shaded. matplotlib is imported here only.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from voe.gap.output import atomic_write
from voe.gap.shooting import make_windows


def _save(fig, path: Path) -> None:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    atomic_write(path, buf.getvalue())


def _chain(finder, ep_i: int, effect, params) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate consecutive fit windows of episode ``ep_i``: times (N,) and poses (N, B, 3)."""
    sh = finder._shooter
    ts, ps = [], []
    for w in make_windows(sh.episodes, [ep_i], finder.config.fit_window):
        ts.append(sh.episodes[ep_i].t[w.k0:w.k1 + 1])
        ps.append(sh.simulate(w, effect, params))
        ts.append([np.nan])
        ps.append(np.full((1,) + ps[-1].shape[1:], np.nan))
    return np.concatenate(ts), np.concatenate(ps)


def figures(finder, out: Path) -> list[str]:
    """Render both figures into ``out``; returns their file names."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sh, names = finder._shooter, finder.scene_.names
    ep_i = finder._test_ids[0]
    ep = sh.episodes[ep_i]
    t0, p0 = _chain(finder, ep_i, None, None)
    t1, p1 = _chain(finder, ep_i, finder.effect_, finder.params_) if finder.effect_ is not None else (t0, p0)
    fig, axes = plt.subplots(2 * len(names), 3, figsize=(12, 4.4 * len(names)), squeeze=False)
    rec = np.interp(t0, ep.t, np.arange(len(ep.t)))  # sample index of each plotted time
    idx = np.where(np.isfinite(rec), np.round(np.nan_to_num(rec)), 0).astype(int)
    for b, name in enumerate(names):
        for v, var in enumerate(("x", "y", "angle")):
            ax, axr = axes[2 * b, v], axes[2 * b + 1, v]
            ax.plot(ep.t, ep.pose[:, b, v], "k.", ms=2, label="recorded")
            ax.plot(t0, p0[:, b, v], "r-", lw=1, label="nominal")
            axr.plot(t0, p0[:, b, v] - ep.pose[idx, b, v], "r-", lw=0.8, label="nominal - recorded")
            if finder.effect_ is not None:
                ax.plot(t1, p1[:, b, v], "b-", lw=1, label="with fitted effects")
                axr.plot(t1, p1[:, b, v] - ep.pose[idx, b, v], "b-", lw=0.8, label="fitted - recorded")
            ax.set_title(f"{name} {var}")
            axr.set_title(f"{name} {var} residual")
            axr.set_xlabel("t (s)")
    axes[1, 0].legend(fontsize=7)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"held-out episode {ep.id}: {finder.config.fit_window:g} s re-initialised windows")
    _save(fig, out / "trajectories.png")
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(10, 3.2))
    shown = sorted({w.ep for w in finder._loc_windows})[:3]
    offset = 0.0
    for ep_j in shown:
        e = sh.episodes[ep_j]
        for w in (w for w in finder._loc_windows if w.ep == ep_j):
            r = np.linalg.norm(sh.residual(w, None, None), axis=2).max(axis=1)  # (n,)
            ax.semilogy(offset + e.t[w.k0:w.k1 + 1] - e.t[0], np.maximum(r, 1e-9), "r-", lw=0.8)
        for x in finder.located_:
            if x["episode"] == e.id:
                ax.axvspan(offset + x["t_start"] - e.t[0], offset + x["t_end"] - e.t[0], color="orange", alpha=0.3)
        ax.axvline(offset, color="gray", lw=0.5)
        offset += float(e.t[-1] - e.t[0])
    ax.set_xlabel(f"time (s), episodes {[sh.episodes[j].id for j in shown]} back to back")
    ax.set_ylabel("nominal residual (m)")
    ax.set_title("residual of the nominal model in re-initialised windows; located stretches shaded")
    _save(fig, out / "residual.png")
    plt.close(fig)
    return ["trajectories.png", "residual.png"]


def markdown(finder, figs: list[str]) -> str:
    """The text of ``gap.md``."""
    f = finder.fit_
    lines = [f"# Sim-to-real gap: {finder.verdict_}", "", finder.explanation_, "",
             "## Fit on held-out episodes", "",
             "| | before | after |", "|---|---|---|",
             f"| RMSE (x, y, angle*sqrt(I/m)) | {f['before']:.4g} m | {f['after']:.4g} m |",
             f"| position RMSE | {f['position_before']:.4g} m | {f['position_after']:.4g} m |",
             f"| median standardised residual | {f['median_z_before']:.3g} | {f['median_z_after']:.3g} |", "",
             f"Held-out episodes {f['holdout_episodes']}; acceptance threshold {100 * f['threshold_gain']:.1f} % "
             "held-out improvement (from the null run on simulated clean data).", "", "## Effects", ""]
    if finder.effects_:
        lines += ["| effect | parameters | bodies |", "|---|---|---|"]
        for e in finder.effects_:
            ps = ", ".join(f"{k} = {v:.4g} {e['units'][k]}" for k, v in e["params"].items())
            lines.append(f"| {e['name']} | {ps} | {', '.join(e['bodies'])} |")
        for g in finder.groups_:
            if len(g) > 1:
                lines.append(f"\nIndistinguishable on these data: {', '.join(g)}.")
    else:
        lines.append("None accepted.")
    lines += ["", "## Located", ""]
    if finder.located_:
        lines += ["| episode | body | t (s) | variables | context | z |", "|---|---|---|---|---|---|"]
        for x in finder.located_[:40]:
            lines.append(f"| {x['episode']} | {x['body']} | {x['t_start']:.2f}-{x['t_end']:.2f} | "
                         f"{', '.join(x['variables'])} | {x['context']} | {x['z']:.1f} |")
        if len(finder.located_) > 40:
            lines.append(f"\n... and {len(finder.located_) - 40} more in gap.json.")
    else:
        lines.append("No stretch exceeds the null-calibrated threshold.")
    lines += ["", "## Figures", ""] + [f"![{n}]({n})" for n in figs] + [""]
    return "\n".join(lines)


def write_report(finder, out: Path) -> None:
    """Render figures and write ``gap.md`` into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    figs = figures(finder, out)
    atomic_write(out / "gap.md", markdown(finder, figs))
