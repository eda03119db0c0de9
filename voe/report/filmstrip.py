"""Filmstrips of a matched set (PNG) and animations (GIF), with the violation onset marked.

Why: a researcher checks a probe by looking at it; one row per clip, frames left to right, the
onset frame outlined in red, makes a splice or a violation obvious at a glance.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from voe.io.atomic import atomic_write_bytes


def filmstrip_figure(frames: Sequence[np.ndarray], labels: Sequence[str], onset: Sequence[int],
                     every: int = 2, traces: Sequence[np.ndarray] | None = None, title: str = "",
                     unit: str = "nats"):
    """A matplotlib figure: one row per clip (frames ``(T, H, W)``), optional surprise traces.

    Args:
        frames: per clip, ``(T, H, W)`` uint8.
        labels: per clip, a row label (variant and role).
        onset: per clip, the onset frame (outlined in red).
        every: show every ``every``-th frame (the onset frame is always shown).
        traces: per clip, an optional ``(T,)`` surprise trace drawn under its strip.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    T = frames[0].shape[0]
    shown = sorted(set(range(0, T, every)) | set(int(o) for o in onset))
    n = len(frames)
    rows = n * (2 if traces is not None else 1)
    heights = [1.0, 0.6] * n if traces is not None else [1.0] * n
    ylim = None
    if traces is not None:  # one y scale for every trace, so heights compare across clips
        vals = np.concatenate([np.asarray(tr, dtype=float).ravel() for tr in traces])
        vals = vals[np.isfinite(vals)]
        if vals.size:
            lo, hi = float(vals.min()), float(vals.max())
            pad = 0.08 * (hi - lo) if hi > lo else 0.5
            ylim = (lo - pad, hi + pad)
    fig = plt.figure(figsize=(min(0.55 * len(shown), 22), 0.75 * sum(heights) + 0.5))
    gs = fig.add_gridspec(rows, len(shown), height_ratios=heights, wspace=0.04,
                          hspace=0.35 if traces is not None else 0.15)
    for c, (clip, label) in enumerate(zip(frames, labels, strict=True)):
        r = c * (2 if traces is not None else 1)
        for j, t in enumerate(shown):
            ax = fig.add_subplot(gs[r, j])
            ax.imshow(clip[t], cmap="gray", vmin=0, vmax=255, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if t == onset[c]:
                for s in ax.spines.values():
                    s.set_edgecolor("red")
                    s.set_linewidth(2.5)
            if c == 0:
                ax.set_title(f"t={t}", fontsize=6)
            if j == 0:
                ax.set_ylabel(label, fontsize=7, rotation=0, ha="right", va="center")
        if traces is not None:
            ax = fig.add_subplot(gs[r + 1, :])
            ax.plot(np.arange(T), traces[c], color="tab:red" if "imp" in label else "tab:blue", lw=1.2)
            ax.axvline(onset[c], color="red", ls="--", lw=0.8)
            ax.set_xlim(-0.5, T - 0.5)
            if ylim is not None:
                ax.set_ylim(*ylim)
            ax.tick_params(labelsize=6)
            ax.set_ylabel(unit, fontsize=6)
    if title:
        fig.suptitle(title, fontsize=9)
    return fig


def save_figure(fig, path: Path, dpi: int = 110) -> None:
    """Save a matplotlib figure atomically (PNG or SVG by suffix)."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format=Path(path).suffix.lstrip(".") or "png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    atomic_write_bytes(Path(path), buf.getvalue())


def save_gif(frames: Sequence[np.ndarray], labels: Sequence[str], onset: Sequence[int], path: Path,
             scale: int = 3, fps: int = 10) -> None:
    """An animated GIF with the clips side by side; a red bar marks frames from the onset on."""
    from PIL import Image

    T = frames[0].shape[0]
    pics = []
    for t in range(T):
        tiles = []
        for clip, o in zip(frames, onset, strict=True):
            tile = np.repeat(clip[t][..., None], 3, axis=-1).astype(np.uint8)
            tile = np.pad(tile, ((4, 1), (1, 1), (0, 0)))
            if t >= o:
                tile[:3, :, :] = (220, 30, 30)
            tiles.append(tile)
        img = Image.fromarray(np.concatenate(tiles, axis=1))
        pics.append(img.resize((img.width * scale, img.height * scale), Image.NEAREST))
    buf = io.BytesIO()
    pics[0].save(buf, format="GIF", save_all=True, append_images=pics[1:],
                 duration=int(1000 / fps), loop=0)
    atomic_write_bytes(Path(path), buf.getvalue())
    del labels  # labels are in the filename/caption for GIFs
