"""``voe probes validate``: checksums, schema and frame balance of a probe set on disk."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from voe.errors import ProbeSetError
from voe.io.balance import pair_problem, quadruplet_problem
from voe.io.paths import inside
from voe.io.probeset import ARRAYS, ROLES, ProbeSet
from voe.io.provenance import sha256_file


@dataclass
class ValidationReport:
    """Problems found (empty means valid) and a per-concept balance table."""

    problems: list[str] = field(default_factory=list)
    table: pd.DataFrame | None = None

    @property
    def ok(self) -> bool:
        return not self.problems


def _checksums(ps: ProbeSet, rep: ValidationReport) -> None:
    files = ps.manifest.get("files", {})
    for name in ("index.parquet",) + tuple(f"{a}.npy" for a in ARRAYS):
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
            rep.problems.append(f"{ps.path / (name + '.npy')}: {arr.dtype}{arr.shape}, expected "
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
        nan_rows = np.isnan(np.asarray(ps.array("states"))).all(axis=-1)  # (N, T, K)
        if (nan_rows != ~np.asarray(ps.array("present"))).any():
            rep.problems.append("states.npy: NaN rows do not match present.npy")
    return ok


def _balance(ps: ProbeSet, rep: ValidationReport) -> None:
    frames = ps.array("frames")
    rows = []
    for set_id, g in ps.index.groupby("set_id", sort=True):
        if (g["role"] == "train").all():
            continue
        kind = g["set_kind"].iloc[0] if "set_kind" in g else ("quadruplet" if len(g) == 4 else "pair")
        pos = [np.asarray(frames[r]) for r in g.loc[g.role == "possible", "row"]]
        imp = [np.asarray(frames[r]) for r in g.loc[g.role == "impossible", "row"]]
        if kind == "quadruplet":
            why = quadruplet_problem(pos, imp) if len(pos) == 2 == len(imp) else "not 2+2 clips"
        else:
            why = (pair_problem(pos[0], imp[0], int(g["onset_frame"].iloc[0]))
                   if len(pos) == 1 == len(imp) else "not 1+1 clips")
        if why:
            rep.problems.append(f"set {set_id}: {why}")
        rows.append({"concept": g["concept"].iloc[0], "kind": kind, "balanced": why is None})
    if rows:
        df = pd.DataFrame(rows)
        rep.table = (df.groupby(["concept", "kind"]).agg(n_sets=("balanced", "size"),
                                                         balanced=("balanced", "sum")).reset_index())


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
