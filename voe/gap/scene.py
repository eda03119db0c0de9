"""Read and check a gap-finder ``scene.json`` (format pinned in docs/gap.md).

Why: every mistake in a scene file should stop the run with one line that names the problem and
the file, before any simulation starts. World-frame joint anchors are turned into body-local
anchors from the first recorded pose, which is when the file says they hold.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from voe.errors import DataError
from voe.sim.scenefile import BodySpec, JointSpec, SceneSpec, StaticSpec

_SHAPES = ("circle", "box", "poly")


def load_scene(path: str | Path) -> tuple[SceneSpec, list[dict[str, Any]], dict[str, Any]]:
    """Parse ``scene.json``.

    Returns:
        The scene with joints still unresolved (anchors (0, 0)), the raw joint entries (resolve
        them with ``resolve_joints`` once poses are known) and the optional ``initial`` poses.

    Raises:
        DataError: unreadable JSON or a missing/invalid field; the message names the file.
    """
    path = Path(path)
    try:
        raw = json.loads(path.read_text())
    except FileNotFoundError as exc:
        raise DataError(f"scene file not found: {path}") from exc
    except json.JSONDecodeError as exc:
        raise DataError(f"scene file {path} is not valid JSON: {exc.msg} at line {exc.lineno}") from exc
    except (UnicodeDecodeError, OSError) as exc:
        raise DataError(f"scene file {path} cannot be read as UTF-8 JSON text: {exc}") from exc
    if not isinstance(raw, dict):
        raise DataError(f"scene file {path} must hold a JSON object")
    gravity = _vec(raw.get("gravity", [0.0, -9.81]), "gravity", path)
    bodies_raw = raw.get("bodies")
    if not isinstance(bodies_raw, list) or not bodies_raw:
        raise DataError(f"scene file {path} needs a non-empty 'bodies' list")
    bodies = tuple(_body(b, i, path) for i, b in enumerate(bodies_raw))
    names = [b.name for b in bodies]
    if len(set(names)) != len(names):
        raise DataError(f"scene file {path} has duplicate body names: {names}")
    statics = tuple(_static(s, i, path) for i, s in enumerate(_list(raw, "statics", path)))
    joints = _list(raw, "joints", path)
    for i, j in enumerate(joints):
        if not isinstance(j, dict):
            raise DataError(f"scene file {path}: joint {i} must be an object, got {j!r:.60}")
        if j.get("type", "pivot") != "pivot":
            raise DataError(f"scene file {path}: joint {i} has type {j.get('type')!r}; only 'pivot' is supported")
        if j.get("a") not in names or (j.get("b") is not None and j.get("b") not in names):
            raise DataError(f"scene file {path}: joint {i} names unknown body {j.get('a')!r}/{j.get('b')!r}; bodies are {names}")
        if "anchor" not in j and not ("anchor_a" in j and "anchor_b" in j):
            raise DataError(f"scene file {path}: joint {i} needs 'anchor' or both 'anchor_a' and 'anchor_b'")
    initial = raw.get("initial") or {}
    if not isinstance(initial, dict):
        raise DataError(f"scene file {path}: 'initial' must be an object of poses by body name")
    for name in initial:
        if name not in names:
            raise DataError(f"scene file {path}: 'initial' names unknown body {name!r}; bodies are {names}")
    scene = SceneSpec(gravity=gravity, bodies=bodies, statics=statics, joints=(), units=raw.get("units", {}))
    return scene, joints, initial


def resolve_joints(scene: SceneSpec, joints: list[dict[str, Any]], pose0: np.ndarray) -> SceneSpec:
    """Return ``scene`` with pivot joints whose anchors are local to each body.

    Args:
        pose0: (B, 3) first recorded pose, where world ``anchor`` points hold.
    """
    index = {n: i for i, n in enumerate(scene.names)}
    out = []
    for j in joints:
        if "anchor" in j:
            w = np.asarray(j["anchor"], dtype=float)
            la = _to_local(w, pose0[index[j["a"]]])
            lb = tuple(w) if j.get("b") is None else _to_local(w, pose0[index[j["b"]]])
        else:
            la, lb = tuple(map(float, j["anchor_a"])), tuple(map(float, j["anchor_b"]))
        out.append(JointSpec(j["a"], j.get("b"), la, lb, bool(j.get("collide_bodies", False))))
    return SceneSpec(scene.gravity, scene.bodies, scene.statics, tuple(out), scene.units)


def _to_local(w: np.ndarray, pose: np.ndarray) -> tuple[float, float]:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    d = w - pose[:2]
    return (float(c * d[0] + s * d[1]), float(-s * d[0] + c * d[1]))


def _vec(v: Any, what: str, path: Path) -> tuple[float, float]:
    try:
        x, y = (float(a) for a in v)
    except (TypeError, ValueError) as exc:
        raise DataError(f"scene file {path}: '{what}' must be [x, y], got {v!r}") from exc
    return (x, y)


def _num(d: dict, key: str, where: str, path: Path, default: float | None = None, positive: bool = False) -> float:
    if key not in d:
        if default is None:
            raise DataError(f"scene file {path}: {where} is missing '{key}'")
        return default
    try:
        val = float(d[key])
    except (TypeError, ValueError) as exc:
        raise DataError(f"scene file {path}: {where} '{key}' must be a number, got {d[key]!r}") from exc
    if not math.isfinite(val) or (positive and val <= 0):
        raise DataError(f"scene file {path}: {where} '{key}' must be {'positive' if positive else 'finite'}, got {val}")
    return val


def _body(b: dict, i: int, path: Path) -> BodySpec:
    if not isinstance(b, dict) or "name" not in b:
        raise DataError(f"scene file {path}: body {i} needs a 'name'")
    where = f"body {b['name']!r}"
    shape = b.get("shape")
    if shape not in _SHAPES:
        raise DataError(f"scene file {path}: {where} has shape {shape!r}; use one of {', '.join(_SHAPES)}")
    kw: dict[str, Any] = {}
    if shape == "circle":
        kw["radius"] = _num(b, "radius", where, path, positive=True)
    elif shape == "box":
        kw["size"] = _vec(b.get("size"), f"{where} size", path)
        if min(kw["size"]) <= 0:
            raise DataError(f"scene file {path}: {where} size must be positive, got {kw['size']}")
    else:
        verts = b.get("vertices")
        if not isinstance(verts, list) or len(verts) < 3:
            raise DataError(f"scene file {path}: {where} poly needs at least 3 'vertices'")
        kw["vertices"] = tuple(_vec(v, f"{where} vertex", path) for v in verts)
    moment = _num(b, "moment", where, path, positive=True) if "moment" in b else None
    return BodySpec(name=str(b["name"]), shape=shape, mass=_num(b, "mass", where, path, positive=True),
                    moment=moment, friction=_num(b, "friction", where, path, 0.5),
                    elasticity=_num(b, "elasticity", where, path, 0.0), **kw)


def _list(raw: dict[str, Any], key: str, path: Path) -> list[Any]:
    """``raw[key]`` as a list (absent or null: empty); anything else is refused naming the key."""
    value = raw.get(key) or []
    if not isinstance(value, list):
        raise DataError(f"scene file {path}: '{key}' must be a list, got {type(value).__name__}")
    return value


def _static(s: dict, i: int, path: Path) -> StaticSpec:
    if not isinstance(s, dict):
        raise DataError(f"scene file {path}: static {i} must be an object, got {s!r:.60}")
    where = f"static {i}"
    if s.get("shape", "segment") != "segment":
        raise DataError(f"scene file {path}: {where} has shape {s.get('shape')!r}; only 'segment' is supported")
    return StaticSpec(a=_vec(s.get("a"), f"{where} a", path), b=_vec(s.get("b"), f"{where} b", path),
                      radius=_num(s, "radius", where, path, 0.0), friction=_num(s, "friction", where, path, 0.5),
                      elasticity=_num(s, "elasticity", where, path, 0.0))
