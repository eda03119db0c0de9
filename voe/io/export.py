"""Export a probe set for outside tools: clips as mp4 or PNG frames, a metadata table, an answer key.

Why: video world models (V-JEPA, Cosmos, video diffusion) read mp4 files or frame folders plus a
metadata table, often through Hugging Face ``datasets``. The export gives them voe's clips
without giving the answer away:

* clips are **redrawn from the stored states** (``voe.sim.render``), natively at ``size`` pixels and
  in colour with ``rgb`` (one colour per object slot), never upscaled from 64 px. At the probe
  set's own size and in grayscale the redrawn frames are byte-identical to the stored ones (the
  generator draws with the same function; ``tests/io/test_export.py`` checks every concept);
* file names are opaque keys (``voe.io.clipkey``), rows are sorted by key, and the table holds
  only what a model may know (concept, condition, onset frame). Which clip is impossible is
  written only to ``answers.parquet``;
* ``layout="intphys"`` writes the IntPhys dev layout instead (``block/set/run/scene/scene_001.png``
  and ``run/status.json`` with ``header.is_possible``), so IntPhys tools run unchanged on voe's
  quadruplets. Runs are numbered by key order, not by role. A pair (two-clip set) has runs 1
  and 2 only; tools that assume four runs should read the quadruplet blocks listed in the
  export manifest (``intphys.quadruplet_blocks``);
* the whole directory is written to a temporary sibling and renamed (atomic), with a manifest
  holding the sha256 of every file, the source probe set's manifest sha256, versions and options.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from voe import __version__
from voe.errors import VoeError
from voe.io import jsonio
from voe.io.atomic import atomic_dir
from voe.io.clipkey import clip_key, set_key
from voe.io.outputs import check_output
from voe.io.probeset import ProbeSet, load_probe_set
from voe.io.provenance import package_versions, sha256_file
from voe.io.video import MP4_PARAMS, MP4_PIX_FMT, ffmpeg_version, write_mp4, write_pngs
from voe.parallel import parallel_map
from voe.sim.render import render_clip

FORMATS = ("mp4", "png")
LAYOUTS = ("flat", "intphys")
SIZE_RANGE = (16, 1024)
SCHEMA_VERSION = 1


@dataclass(frozen=True)
class ExportOptions:
    """How clips are written. ``validate`` turns a bad choice into one line naming the option."""

    fmt: str = "mp4"
    size: int = 224
    rgb: bool = False
    layout: str = "flat"

    def validate(self) -> None:
        if self.fmt not in FORMATS:
            raise VoeError(f"unknown --format '{self.fmt}' (known: {', '.join(FORMATS)})")
        if self.layout not in LAYOUTS:
            raise VoeError(f"unknown --layout '{self.layout}' (known: {', '.join(LAYOUTS)})")
        lo, hi = SIZE_RANGE
        if not (isinstance(self.size, int | np.integer) and lo <= self.size <= hi):
            raise VoeError(f"--size {self.size}: use a frame side from {lo} to {hi} pixels")
        if self.layout == "intphys" and self.fmt != "png":
            raise VoeError("--layout intphys writes PNG frames as IntPhys does; use --format png")


def _plan(ps: ProbeSet, layout: str) -> pd.DataFrame:
    """One row per clip with its keys, condition and relative path, sorted by clip key."""
    sha = ps.manifest_sha256
    idx = ps.index
    df = pd.DataFrame({
        "clip_id": idx["clip_id"].astype(str), "set_id": idx["set_id"].astype(str),
        "concept_id": idx["concept"].astype(str),
        "concept": idx["concept"].astype(str).str.split("-v").str[0].str.lower(),
        "condition": (idx["condition"].astype(str) if "condition" in idx
                      else np.where(idx["visible_violation"].astype(bool), "visible", "occluded")),
        "n_distractors": idx["n_distractors"].astype(int), "set_kind": idx.get("set_kind", "quadruplet"),
        "onset_frame": idx["onset_frame"].astype(int), "variant": idx["variant"].astype(str),
        "role": idx["role"].astype(str), "geometry": idx["geometry"].astype(str),
    })
    df["clip_key"] = [clip_key(sha, c) for c in df["clip_id"]]
    df["set_key"] = [set_key(sha, s) for s in df["set_id"]]
    df = df.sort_values("clip_key", kind="stable").reset_index(drop=True)
    if layout == "flat":
        df["path"] = [f"clips/{k[:2]}/{k}" for k in df["clip_key"]]
        return df
    # intphys: block = concept, sets numbered in key order, runs numbered in key order within a set
    df["run"] = df.groupby("set_key").cumcount() + 1
    paths = []
    for concept, g in df.groupby("concept", sort=True):
        order = {k: i + 1 for i, k in enumerate(sorted(g["set_key"].unique()))}
        width = max(2, len(str(len(order))))
        for i, row in g.iterrows():
            paths.append((i, f"{concept}/{order[row.set_key]:0{width}d}/{row.run}"))
    df["path"] = pd.Series(dict(paths))
    return df


def _write_set(ps: ProbeSet, root: Path, opts: ExportOptions, fps: float, rows: pd.DataFrame) -> dict[str, str]:
    """Render and write the clips of one matched set; returns ``{relative path: sha256}``."""
    data = ps.get(list(rows["clip_id"]))
    files: dict[str, Path] = {}
    for i, row in enumerate(rows.itertuples()):
        frames = render_clip(data["states"][i], data["present"][i], json.loads(row.geometry),
                             opts.size, opts.rgb)  # (T, S, S[, 3]) uint8
        base = root / row.path
        if opts.layout == "intphys":
            for p in write_pngs(base / "scene", frames, name="scene_{:03d}.png", first=1):
                files[p.relative_to(root).as_posix()] = p
            status = {"header": {"block_name": row.concept, "block_type": "test",
                                 "is_possible": row.role == "possible", "clip_key": row.clip_key,
                                 "set_key": row.set_key, "onset_frame": int(row.onset_frame)},
                      "frames": [{} for _ in range(len(frames))]}
            (base / "status.json").write_text(jsonio.dumps(status, indent=4) + "\n")
            files[f"{row.path}/status.json"] = base / "status.json"
        elif opts.fmt == "png":
            for p in write_pngs(base, frames):
                files[p.relative_to(root).as_posix()] = p
        else:
            base.parent.mkdir(parents=True, exist_ok=True)
            write_mp4(base.with_suffix(".mp4"), frames, fps)
            files[f"{row.path}.mp4"] = base.with_suffix(".mp4")
    return {rel: sha256_file(p) for rel, p in files.items()}


def _tables(plan: pd.DataFrame, opts: ExportOptions, n_frames: int, fps: float) -> tuple[pd.DataFrame, pd.DataFrame]:
    meta = plan[["clip_key", "path", "concept", "concept_id", "condition", "n_distractors", "set_key",
                 "set_kind", "onset_frame"]].copy()
    if opts.fmt == "mp4":
        meta["path"] = meta["path"] + ".mp4"
    meta["n_frames"], meta["fps"], meta["height"], meta["width"] = n_frames, fps, opts.size, opts.size
    meta["channels"] = 3 if opts.rgb else 1
    answers = plan[["clip_key", "set_key", "clip_id", "set_id", "variant", "role"]].copy()
    answers["is_possible"] = answers["role"] == "possible"
    return meta, answers


def export_probe_set(probes: str | Path, out: str | Path, fmt: str = "mp4", size: int = 224,
                     rgb: bool = False, layout: str = "flat", overwrite: bool = False, jobs: int = 1,
                     progress: Callable[[int], None] | None = None) -> dict[str, Any]:
    """Write the clips of probe set ``probes`` to ``out`` for outside tools; returns the manifest.

    Args:
        fmt: ``mp4`` (needs the ``video`` extra) or ``png`` (one file per frame).
        size: frame side in pixels; frames are drawn natively at this size.
        rgb: colour frames, one colour per object slot; grayscale otherwise.
        layout: ``flat`` (``clips/`` + tables) or ``intphys`` (the IntPhys dev layout, + tables).
        jobs: processes (matched sets are written in parallel; output is identical for any value).
        progress: called with 1 per matched set written.

    Raises:
        VoeError: an unknown format or layout, a bad size, or ``out`` exists and is not empty.
    """
    opts = ExportOptions(fmt, size, rgb, layout)
    opts.validate()
    out = check_output(out, "dir", overwrite)
    ps = load_probe_set(probes)
    fps = 1.0 / ps.dt
    plan = _plan(ps, layout)
    n_frames = int(ps.manifest.get("n_frames", 0))
    versions = package_versions(("numpy", "pandas", "pyarrow", "pillow", "imageio-ffmpeg"))
    if fmt == "mp4":
        versions["ffmpeg"] = ffmpeg_version()
    with atomic_dir(out, overwrite=overwrite) as tmp:
        groups = [g for _, g in plan.groupby("set_key", sort=True)]
        files: dict[str, str] = {}
        for written in parallel_map(lambda g: _write_set(ps, tmp, opts, fps, g), groups, jobs, progress):
            files.update(written)
        meta, answers = _tables(plan, opts, n_frames, fps)
        for name, df in (("metadata", meta), ("answers", answers)):
            df.to_parquet(tmp / f"{name}.parquet", index=False, engine="pyarrow")
            files[f"{name}.parquet"] = sha256_file(tmp / f"{name}.parquet")
        meta.to_csv(tmp / "metadata.csv", index=False)
        files["metadata.csv"] = sha256_file(tmp / "metadata.csv")
        manifest = {
            "kind": "voe-export", "schema_version": SCHEMA_VERSION, "voe_version": __version__,
            "versions": versions,
            "source": {"path": str(probes), "manifest_sha256": ps.manifest_sha256,
                       "n_clips": len(plan)},
            "options": {**asdict(opts), "fps": fps, "n_frames": n_frames,
                        **({"mp4": {"codec": "libx264", "pix_fmt": MP4_PIX_FMT,
                                    "params": list(MP4_PARAMS)}} if fmt == "mp4" else {})},
            "n_clips": len(plan),
            "files": dict(sorted(files.items())),
        }
        if layout == "intphys":
            kinds = plan.groupby("concept")["set_kind"].first()
            manifest["intphys"] = {
                "quadruplet_blocks": sorted(kinds.index[kinds == "quadruplet"]),
                "pair_blocks": sorted(kinds.index[kinds == "pair"]),
                "mirrored_blocks": sorted(kinds.index[kinds == "mirrored"]),
                "pairs": "two runs (1, 2) per set; runs are numbered in clip-key order, not by role",
                "mirrored": "four runs per set (a pair and its left-right mirror), numbered like pairs"}
        (tmp / "manifest.json").write_text(jsonio.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return manifest

