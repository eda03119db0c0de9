"""Write ``gap.md`` and its figures from a fitted ``GapFinder``.

Why: a reader should see the mismatch, not only read about it. Two figures: recorded versus
simulated trajectories (nominal and with the fitted effects) on a held-out episode, and the
nominal residual over time with the located stretches shaded. matplotlib is imported here only.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from voe.gap.locate import LOCAL
from voe.gap.output import atomic_write
from voe.gap.search import GROUP_TOL
from voe.gap.shooting import make_windows


def _save(fig, path: Path) -> None:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    atomic_write(path, buf.getvalue())


def _windows(finder, ep_i: int, effect, params) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every other fit window of episode ``ep_i``, simulated: [(times (n,), poses (n, B, 3))].

    Every other window, so that gaps separate them: each window restarts from the recording,
    and lines joined across a restart would draw jumps that are not in any simulation.
    """
    p = finder.problem_
    ws = make_windows(p.episodes, [ep_i], finder.config.fit_window, bad_start=p.bad)[::2]
    return [(p.episodes[ep_i].t[w.k0:w.k1 + 1], p.shooter.simulate(w, effect, params)) for w in ws]


def _moving(ep, sigma: np.ndarray) -> list[tuple[int, int]]:
    """(body, variable) pairs whose recorded range exceeds 20 noise sigmas: only what moves is plotted."""
    rng = np.ptp(ep.pose, axis=0)  # (B, 3)
    return [(b, v) for b in range(rng.shape[0]) for v in range(3) if rng[b, v] > 20 * sigma[b, v]]


def _test_episode(finder) -> tuple[int, np.ndarray | None]:
    """Index of the first test episode and its parameters (its fold's in cross-validation)."""
    split, m = finder.problem_.split, finder.checked_.model
    if split.cross_validated:
        return split.folds[0][2][0], (m.fold_params[0] if m is not None else None)
    return split.test[0], (m.params if m is not None else None)


def figures(finder, out: Path) -> list[str]:
    """Render both figures into ``out``; returns their file names."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = finder.problem_
    sh, names = p.shooter, p.scene.names
    ep_i, params = _test_episode(finder)
    ep = sh.episodes[ep_i]
    shown = _moving(ep, p.sigma) or [(0, 0)]
    nom = _windows(finder, ep_i, None, None)
    fitted = _windows(finder, ep_i, finder.effect_, params) if finder.effect_ is not None else []
    fig, axes = plt.subplots(2, len(shown), figsize=(4 * len(shown), 5.5), squeeze=False, layout="constrained")
    for c, (b, v) in enumerate(shown):
        ax, axr = axes[0, c], axes[1, c]
        ax.plot(ep.t, ep.pose[:, b, v], "k.", ms=2, label="recorded")
        for label, runs, col in (("nominal", nom, "r"), ("with fitted effects", fitted, "b")):
            for n, (t, pose) in enumerate(runs):
                k0 = int(np.searchsorted(ep.t, t[0] - 1e-9))
                ax.plot(t, pose[:, b, v], f"{col}-", lw=1, label=label if n == 0 else None)
                axr.plot(t, pose[:, b, v] - ep.pose[k0:k0 + len(t), b, v], f"{col}-", lw=0.8,
                         label=f"{label} - recorded" if n == 0 else None)
        ax.set_title(f"{names[b]} {('x', 'y', 'angle')[v]}")
        axr.set_title(f"{names[b]} {('x', 'y', 'angle')[v]} residual")
        axr.set_xlabel("t (s)")
    axes[0, 0].legend(fontsize=7)
    axes[1, 0].legend(fontsize=7)
    fig.suptitle(f"test episode {ep.id}: every other {finder.config.fit_window:g} s window, each re-initialised "
                 "from the recording")
    _save(fig, out / "trajectories.png")
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(10, 3.2))
    wins = finder.location_.windows
    shown_eps = sorted({w.ep for w in wins})[:3]
    offset = 0.0
    for ep_j in shown_eps:
        e = sh.episodes[ep_j]
        for w in (w for w in wins if w.ep == ep_j):
            r = np.linalg.norm(sh.residual(w, None, None), axis=2).max(axis=1)  # (n,)
            ax.semilogy(offset + e.t[w.k0:w.k1 + 1] - e.t[0], np.maximum(r, 1e-9), "r-", lw=0.8)
        for x in finder.located_:
            if x["episode"] == e.id:
                ax.axvspan(offset + x["t_start"] - e.t[0], offset + x["t_end"] - e.t[0], color="orange", alpha=0.3)
        ax.axvline(offset, color="gray", lw=0.5)
        offset += float(e.t[-1] - e.t[0])
    ax.set_xlabel(f"time (s), episodes {[sh.episodes[j].id for j in shown_eps]} back to back")
    ax.set_ylabel("nominal residual (m)")
    ax.set_title("residual of the nominal model in re-initialised windows; located stretches shaded")
    _save(fig, out / "residual.png")
    plt.close(fig)
    return ["trajectories.png", "residual.png"]


def _bar(x: dict, z_floor: float) -> str:
    """The bar a located stretch passed, in words (``voe.gap.locate.Located.bar``); ``z_floor`` is
    the location's floor (``GapConfig.z_min``), named as a number as the explanation names it."""
    if x["bar"] == LOCAL:
        return f"{x['bar_z']:.1f}: each window above its own clean replicates and z = {z_floor:g}"
    return f"{x['bar_z']:.1f}: the clean replicate's 95th-percentile window z"


def markdown(finder, figs: list[str]) -> str:
    """The text of ``gap.md``."""
    f = finder.fit_
    lines = [f"# Sim-to-real gap: {finder.verdict_}", "", finder.explanation_, "",
             "## Fit on the test episodes", "",
             "| | before | after |", "|---|---|---|",
             f"| RMSE (x, y, angle*sqrt(I/m)) | {f['before']:.4g} m | {f['after']:.4g} m |",
             f"| position RMSE | {f['position_before']:.4g} m | {f['position_after']:.4g} m |",
             f"| median standardised residual | {f['median_z_before']:.3g} | {f['median_z_after']:.3g} |", "",
             f"Figures on {f['on']}. {finder.problem_.split.note}. Acceptance threshold (round 1) "
             f"{100 * f['threshold_gain']:.1f} % selection-error improvement, from the identical search on "
             "simulated clean data." + _jitter_note(finder.problem_.jitter), "", "## Effects", ""]
    if finder.effects_:
        lines += ["| effect | parameters (95 % interval) | acts | bodies |", "|---|---|---|---|"]
        for e in finder.effects_:
            ps = ", ".join(f"{k} = {v:.4g} ({e['interval95'][k][0]:.3g} to {e['interval95'][k][1]:.3g}) {e['units'][k]}"
                           for k, v in e["params"].items())
            lines.append(f"| {e['name']} | {ps} | {e['acts']} | {', '.join(e['bodies'])} |")
        lines += _group_lines(finder.groups_, [r.tie for r in finder._kept_rounds()])
    else:
        lines.append("None accepted.")
    for d in finder.checked_.dropped:
        lines.append(f"\nDropped {d['effect']}: {d['reason']}.")
    lines += ["", "## Located", ""]
    if finder.located_:
        lines += ["| episode | body | t (s) | variables | context | z | bar passed |", "|---|---|---|---|---|---|---|"]
        for x in finder.located_[:40]:
            lines.append(f"| {x['episode']} | {x['body']} | {x['t_start']:.2f}-{x['t_end']:.2f} | "
                         f"{', '.join(x['variables'])} | {x['context']} | {x['z']:.1f} | {_bar(x, finder.config.z_min)} |")
        if len(finder.located_) > 40:
            lines.append(f"\n... and {len(finder.located_) - 40} more in gap.json.")
    else:
        lines.append("No stretch exceeds the null-calibrated threshold.")
    if figs:
        lines += ["", "## Figures", ""] + [f"![{n}]({n})" for n in figs]
    return "\n".join(lines + [""])


def _jitter_note(jitter) -> str:
    """A sentence on the timing jitter the clean data reproduce (``voe.gap.jitter``), if any."""
    if jitter is None:
        return ""
    return (f" The samples are taken off their time stamps by about {1e3 * jitter.seconds:.2g} ms (timing jitter, "
            "estimated from the recordings); the clean data reproduce it.")


def _group_lines(groups: list[list[str]], ties: list) -> list[str]:
    """One line per tied group: "indistinguishable" only when no selection window told its members
    apart (``tie`` None); otherwise on how many windows the named member was chosen, and which
    members those windows could not rule out (``voe.gap.search.TieBreak``)."""
    out = []
    for g, tie in zip(groups, ties, strict=True):
        if len(g) < 2:
            continue
        if tie is None:
            out.append(f"\nIndistinguishable on these data (predictions differ in no selection window): {', '.join(g)}.")
        else:
            close = [k for k in g[1:] if k not in tie.unproven]
            text = f"\n{g[0]} chosen on the {tie.n_differ} selection windows where the group's predictions differ"
            if close:
                text += f"; {', '.join(close)} fit those windows within {GROUP_TOL * 100:.0f} % of it"
            if tie.unproven:
                text += f"; too few windows to rule out {', '.join(tie.unproven)} (one-sided sign test)"
            out.append(text + ".")
    return out


def write_report(finder, out: Path, figures_too: bool = True) -> None:
    """Write ``gap.md`` into ``out``, with its figures unless ``figures_too`` is False."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    figs = figures(finder, out) if figures_too else []
    atomic_write(out / "gap.md", markdown(finder, figs))
