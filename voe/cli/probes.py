"""``voe probes``: list concepts, generate, validate and show probe sets."""

from __future__ import annotations

from pathlib import Path

import typer

from voe.cli.common import claims_output
from voe.errors import ProbeSetError

app = typer.Typer(help="Generate, validate and look at probe sets.", no_args_is_help=True)


@app.command("list")
def list_concepts() -> None:
    """List registered concepts and suites."""
    import sys

    from voe.concepts import CONCEPTS, SUITES, get_concept

    for cid in CONCEPTS.ids():
        c = get_concept(cid)
        doc = ((sys.modules[type(c).__module__].__doc__ or type(c).__doc__ or "").strip().splitlines() or [""])[0]
        typer.echo(f"{cid:<22} {c.kind:<10} {doc}")
    for name, members in SUITES.items():
        typer.echo(f"suite {name}: {', '.join(members)}")


@app.command()
@claims_output("dir")
def generate(
    out: Path = typer.Option(..., "--out", help="Directory to write (must be new or empty)."),
    suite: str = typer.Option("core", help="Suite of concepts."),
    concept: list[str] = typer.Option(None, "--concept", help="Only these concepts (repeatable)."),
    per_concept: int = typer.Option(20, "--per-concept", min=1, help="Matched sets per concept."),
    seed: int = typer.Option(0, help="Master seed; the same seed gives byte-identical sets."),
    jobs: int = typer.Option(1, min=1, help="Worker processes."),
    size: int = typer.Option(64, min=32, max=256, help="Frame side in pixels."),
    overwrite: bool = typer.Option(False, help="Replace an existing output directory."),
) -> None:
    """Generate a balanced probe set."""
    from voe.cli.common import progress
    from voe.concepts.generate import generate_probe_set, resolve_concepts
    from voe.sim.scene import SimConfig

    ids = resolve_concepts(None if concept else suite, concept)
    cfg = SimConfig(size=size)
    with progress(len(ids) * per_concept, "matched sets", "set") as tick:
        m = generate_probe_set(out, ids, per_concept, seed, cfg, jobs, overwrite, tick)
    typer.echo(f"wrote {m['n_clips']} clips of {len(ids)} concepts to {out}")


@app.command()
def validate(
    path: Path = typer.Argument(..., help="Probe-set directory."),
    out: Path = typer.Option(None, "--out", help="Where to record the per-set balance "
                             "(default: PATH/balance.parquet)."),
) -> None:
    """Check checksums, schema and the balance each matched set reaches (F, M, T_k, P, V, H, D, X, Y);
    record it; exit 1 on any problem, e.g. a set that reaches less than its concept claims."""
    from voe.io.probeset import load_probe_set
    from voe.io.validate import validate_probe_set, write_balance

    rep = validate_probe_set(load_probe_set(path))
    if rep.table is not None:
        typer.echo(rep.table.to_string(index=False))
    if rep.sets is not None:
        typer.echo(f"balance per set: {write_balance(rep, out or path / 'balance.parquet')}")
    if not rep.ok:
        for p in rep.problems[:20]:
            typer.echo(f"problem: {p}")
        raise ProbeSetError(f"{path}: {len(rep.problems)} problem(s), first: {rep.problems[0]}")
    typer.echo(f"{path}: valid ({rep.table['concept'].nunique() if rep.table is not None else 0} concepts)")


@app.command()
@claims_output("file", (".png", ".svg", ".gif"))
def show(
    path: Path = typer.Argument(..., help="Probe-set directory."),
    set_id: str = typer.Option(..., "--set", help="Matched-set id, e.g. permanence-0003."),
    out: Path = typer.Option(..., "--out", help="Output .png (filmstrip) or .gif (animation)."),
    every: int = typer.Option(2, min=1, help="Show every N-th frame in the filmstrip."),
    overwrite: bool = typer.Option(False, help="Replace an existing output file."),
) -> None:
    """Draw a matched set as a filmstrip with the onset marked."""
    import difflib

    from voe.io.probeset import load_probe_set
    from voe.report.filmstrip import filmstrip_figure, save_figure, save_gif

    ps = load_probe_set(path)
    g = ps.index[ps.index.set_id == set_id]
    if g.empty:
        close = difflib.get_close_matches(set_id, sorted(ps.index.set_id.unique()), n=3)
        hint = f"; did you mean {', '.join(close)}?" if close else ""
        raise ProbeSetError(f"{path}: no matched set '{set_id}'{hint}")
    g = g.sort_values("role", key=lambda s: s.map({"possible": 0, "impossible": 1}), kind="stable")
    frames = list(ps.get(list(g.clip_id))["frames"])
    labels = [f"{v} ({r})" for v, r in zip(g.variant, g.role, strict=True)]
    onset = [int(o) for o in g.onset_frame]
    if out.suffix.lower() == ".gif":
        save_gif(frames, labels, onset, out)
    elif out.suffix.lower() in (".png", ".svg"):
        row = g.iloc[0]
        title = (f"{row.concept} {set_id}: violation {'visible' if row.visible_violation else 'occluded'}, "
                 f"{row.n_distractors} distractor(s), onset frame {onset[0]} (red)")
        save_figure(filmstrip_figure(frames, labels, onset, every=every, title=title), out)
    else:
        raise ProbeSetError(f"--out {out}: use a .png, .svg or .gif file")
    typer.echo(f"wrote {out}")


@app.command("export")
@claims_output("dir")
def export(
    path: Path = typer.Argument(..., help="Probe-set directory."),
    out: Path = typer.Option(..., "--out", help="Directory to write (must be new or empty)."),
    fmt: str = typer.Option("mp4", "--format", help="mp4 (needs the 'video' extra) or png."),
    size: int = typer.Option(224, help="Frame side in pixels, drawn natively (not upscaled)."),
    rgb: bool = typer.Option(False, "--rgb", help="Colour frames, one colour per object."),
    layout: str = typer.Option("flat", help="flat (clips/ + metadata) or intphys (IntPhys dev layout)."),
    jobs: int = typer.Option(1, min=1, help="Worker processes."),
    overwrite: bool = typer.Option(False, help="Replace an existing output directory."),
) -> None:
    """Export clips for outside tools: opaque names, metadata.parquet/.csv, answers.parquet apart."""
    from voe.io.export import ExportOptions, export_probe_set
    from voe.io.probeset import load_probe_set
    from voe.progress import progress

    ExportOptions(fmt, size, rgb, layout).validate()  # fail before opening anything
    n_sets = load_probe_set(path).index["set_id"].nunique()
    with progress(n_sets, "matched sets", "set") as tick:
        m = export_probe_set(path, out, fmt, size, rgb, layout, overwrite, jobs, tick)
    typer.echo(f"wrote {m['n_clips']} clips ({fmt}, {size} px, {'RGB' if rgb else 'gray'}, "
               f"{layout} layout) to {out}; answer key in {out / 'answers.parquet'}")
