"""``voe probes validate``: checksums, schema and balance of a probe set on disk.

Why: a probe set's promises (every file as the manifest pins it; every matched set at least as
balanced as its concept claims) are checked on the stored bytes, not on how the set was built.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from voe.errors import ProbeSetError
from voe.io.balance import LEVELS, STATE_LEVELS, ClipData, parse_claim, set_problems
from voe.io.paths import inside
from voe.io.probeset import ROLES, ProbeSet
from voe.io.provenance import sha256_file


@dataclass
class ValidationReport:
    """Problems found (empty means valid), the balance each set reaches and a per-condition table."""

    problems: list[str] = field(default_factory=list)
    table: pd.DataFrame | None = None  # per concept and condition: claimed, weakest reached, n ok
    sets: pd.DataFrame | None = None  # per matched set: condition, claimed, reached, each level

    @property
    def ok(self) -> bool:
        return not self.problems


def _checksums(ps: ProbeSet, rep: ValidationReport) -> None:
    files = ps.manifest.get("files", {})
    for name in ["index.parquet", *ps.data_files()]:
        if name not in files:
            rep.problems.append(f"manifest.json lists no checksum for {name}")
    for name, digest in files.items():
        try:
            path = inside(ps.path, name, ps.path / "manifest.json", ProbeSetError)
        except ProbeSetError as exc:
            rep.problems.append(str(exc))
            continue
        if not path.exists():
            rep.problems.append(f"{path} is missing")
        elif sha256_file(path) != digest:
            rep.problems.append(f"{path}: sha256 does not match manifest.json")


def _schema(ps: ProbeSet, rep: ValidationReport) -> bool:
    m, n = ps.manifest, len(ps.index)
    T, K, F = m["n_frames"], m["n_slots"], len(m["feature_names"])
    H, W = m["frame_size"]
    want = {"frames": ((n, T, H, W), np.uint8), "states": ((n, T, K, F), np.float32),
            "present": ((n, T, K), np.bool_), "exists": ((n, T, K), np.bool_)}
    ok = True
    for name, (shape, dtype) in want.items():
        arr = ps.array(name)
        if arr.shape != shape or arr.dtype != dtype:
            rep.problems.append(f"{ps.path} {name}: {arr.dtype}{arr.shape}, expected "
                                f"{np.dtype(dtype)}{shape}")
            ok = False
    if m.get("n_clips") != n:
        rep.problems.append(f"manifest says {m.get('n_clips')} clips, index.parquet has {n}")
    if not ps.index["clip_id"].is_unique:
        rep.problems.append("index.parquet: clip_id is not unique")
    bad_roles = set(ps.index["role"]) - set(ROLES)
    if bad_roles:
        rep.problems.append(f"index.parquet: unknown roles {sorted(bad_roles)}")
    onset = ps.index["onset_frame"].to_numpy()
    if ((onset < 0) | (onset >= T)).any() and (ps.index["role"] != "train").all():
        rep.problems.append("index.parquet: onset_frame outside [0, T)")
    if ok:
        for start in range(0, n, 256):  # a chunk of clips at a time: memory does not grow with n
            rows = np.arange(start, min(n, start + 256))
            nan_rows = np.isnan(ps.array("states")[rows]).all(axis=-1)  # (n, T, K)
            if (nan_rows != ~ps.array("present")[rows]).any():
                rep.problems.append("states.npy: NaN rows do not match present.npy")
                break
    return ok


def _claim(g: pd.DataFrame) -> str:
    """What a set's concept claims: the stored ``balance_claim``, else the registry's declaration."""
    if "balance_claim" in g and isinstance(g["balance_claim"].iloc[0], str):
        return g["balance_claim"].iloc[0]
    from voe.concepts import CONCEPTS, get_concept  # sets written before claims were stored

    cid = g["concept"].iloc[0]
    if cid not in CONCEPTS.ids():
        return ""
    c = get_concept(cid)
    return c.balance.get(c.condition(bool(g["visible_violation"].iloc[0])), "")


def _balance(ps: ProbeSet, rep: ValidationReport) -> None:
    arrays = {name: ps.array(name) for name in ("frames", "states", "present")}
    names = ps.feature_names
    rows = []
    for set_id, g in ps.index.groupby("set_id", sort=True):
        if (g["role"] == "train").all():
            continue
        kind = g["set_kind"].iloc[0] if "set_kind" in g else ("quadruplet" if len(g) == 4 else "pair")
        clips = {role: [ClipData(*(np.asarray(arrays[a][r]) for a in ("frames", "states", "present")))
                        for r in g.loc[g.role == role, "row"]] for role in ("possible", "impossible")}
        claim = _claim(g)
        condition = (g["condition"].iloc[0] if "condition" in g
                     else ("visible" if bool(g["visible_violation"].iloc[0]) else "occluded"))
        try:
            reached, why = set_problems(kind, claim, clips["possible"], clips["impossible"],
                                        int(g["onset_frame"].iloc[0]), names)
        except ValueError as exc:  # an unreadable claim
            reached, why = None, [str(exc)]
        rep.problems += [f"set {set_id} ({g['concept'].iloc[0]}, {condition}): {w}" for w in why]
        row = {"set_id": set_id, "concept": g["concept"].iloc[0], "kind": kind, "condition": condition,
               "carries_verdict": bool(g["carries_verdict"].iloc[0]) if "carries_verdict" in g else True,
               "claimed": claim, "reached": str(reached) if reached else "", "ok": not why}
        row.update({lvl: (reached.T if lvl == "T" else bool(getattr(reached, lvl))) if reached else None
                    for lvl in LEVELS})
        rows.append(row)
    if rows:
        rep.sets = pd.DataFrame(rows)
        rep.table = (rep.sets.groupby(["concept", "condition"], sort=True)
                     .agg(kind=("kind", "first"), verdict=("carries_verdict", "first"),
                          claimed=("claimed", "first"), reached=("reached", _weakest),
                          n_sets=("ok", "size"), ok=("ok", "sum")).reset_index())


def _weakest(reached: pd.Series) -> str:
    """The balance every set of a group reaches (levels common to all, the smallest T)."""
    parsed = [parse_claim(r.replace("none", "")) for r in reached]
    common = set.intersection(*(set(p) for p in parsed)) if parsed else set()
    parts = [lvl for lvl in ("F", "M") if lvl in common]
    parts += [f"T{min(p['T'] for p in parsed)}"] if "T" in common else []
    parts += [lvl for lvl in STATE_LEVELS if lvl in common]
    return "+".join(parts) or "none"


def write_balance(rep: ValidationReport, out: Path) -> Path:
    """Store the per-set balance table (``balance.parquet``) atomically."""
    from voe.io.atomic import atomic_write_bytes

    buf = io.BytesIO()
    (rep.sets if rep.sets is not None else pd.DataFrame()).to_parquet(buf, index=False)
    atomic_write_bytes(out, buf.getvalue())
    return out


def validate_probe_set(ps: ProbeSet) -> ValidationReport:
    """Check a probe set; never raises for problems in the data, lists them instead."""
    rep = ValidationReport()
    _checksums(ps, rep)
    try:
        if _schema(ps, rep):
            _balance(ps, rep)
    except (KeyError, ProbeSetError) as exc:
        rep.problems.append(f"cannot check schema: {exc}")
    return rep
