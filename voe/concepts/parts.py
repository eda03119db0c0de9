"""Building blocks shared by concepts: floor, screens, objects on the floor, onset picking.

Why: every concept stages its event on the same stage (a floor, screens in front, objects of a
few shapes), so the stage is built here once and concept files only describe their event.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voe.sim.rollout import Recording
from voe.sim.scene import Body, Occluder, Segment

FLOOR_Y = 0.6  # top surface of the floor
G = 9.81  # the probes' gravity (units/s^2), as ``Scene.gravity``'s default
PILLAR = 12.0  # height of a pillar screen: above the window's top, so it hides whatever passes behind
FLOOR = Segment((-20.0, FLOOR_Y - 0.1), (30.0, FLOOR_Y - 0.1), 0.1, 0.0, 0.5, "floor")


def floor(friction: float = 0.0, elasticity: float = 0.5) -> Segment:
    """The ground, wider than the window so objects can leave it."""
    return Segment(FLOOR.a, FLOOR.b, FLOOR.radius, friction, elasticity, "floor")


def screen(cx: float, width: float, height: float, bottom: float = FLOOR_Y - 0.3,
           pad: float = 0.0) -> Occluder:
    """A screen standing on the floor, centred at ``cx``.

    ``pad`` widens it on both sides; concepts pass one pixel (``Context.pixel``) so that an object
    hidden "with room to spare" in scene units is also hidden at coarse resolutions, where an
    object within a pixel of the edge still shows (see ``Occluder.contains_box``).
    The screen's top is ``bottom + height``; its lower edge is drawn down to the window's bottom so
    that an object resting on the floor is never within a pixel of it.
    """
    return Occluder(cx - width / 2 - pad, min(bottom, 0.0), cx + width / 2 + pad, bottom + height)


def on_floor(look: dict[str, Any], slot: int, x: float, vx: float = 0.0, **kw: Any) -> Body:
    """A body resting on the floor at ``x``; it slides without rotating (frictionless floor)."""
    return Body(slot=slot, shape=look["shape"], width=look["width"], height=look["height"],
                x=x, y=FLOOR_Y + look["height"] / 2, vx=vx, intensity=look["intensity"],
                friction=kw.pop("friction", 0.0), elasticity=kw.pop("elasticity", 0.3), **kw)


def hidden_frames(rec: Recording, slot: int) -> np.ndarray:
    """Frames where the object exists but is not visible (behind a screen or out of view)."""
    return np.flatnonzero(rec.exists[:, slot] & ~rec.present[:, slot])


def visible_frames(rec: Recording, slot: int, extent: float = 10.0) -> np.ndarray:
    """Frames where the object is in plain view: wholly inside the window, clear of every screen."""
    st = rec.states[:, slot]  # (T, F), NaN when not present
    x, y, w, h = st[:, 0], st[:, 1], st[:, 8], st[:, 9]
    with np.errstate(invalid="ignore"):
        ok = rec.present[:, slot] & (x - w / 2 > 0) & (x + w / 2 < extent) & (y + h / 2 < extent)
        for o in rec.geometry.get("occluders", []):
            ok &= (x + w / 2 < o["x0"]) | (x - w / 2 > o["x1"]) | (y - h / 2 > o["y1"])
    return np.flatnonzero(ok)


def pick(frames: np.ndarray, u: float, lo: int, hi: int, what: str) -> int:
    """Pick one of ``frames`` within ``[lo, hi)`` using the uniform number ``u``.

    Raises:
        ValueError: no candidate frame; the concept's parameter ranges are inconsistent.
    """
    cand = frames[(frames >= lo) & (frames < hi)]
    if cand.size == 0:
        raise ValueError(f"no candidate frame for {what} in [{lo}, {hi})")
    return int(cand[min(int(u * cand.size), cand.size - 1)])


#: Frames of context a hidden splice keeps identical on each side (``T_k`` balance, VALIDITY.md).
SPLICE_K = 2


def splice_frames(hidden: np.ndarray, k: int = SPLICE_K) -> np.ndarray:
    """Frames ``s`` of ``hidden`` (sorted frame numbers) with ``s - k .. s + k - 1`` all in it.

    Why: a splice at ``s`` of two clips that are pixel-identical on those ``2k`` frames reaches
    ``T_k`` balance: every window of up to ``k + 1`` frames that straddles the splice also occurs in
    one of the two possible clips, so the amount of motion (``M``) is balanced too.
    """
    have = set(int(t) for t in hidden)
    return np.array([s for s in sorted(have) if all(t in have for t in range(s - k, s + k))], dtype=int)


def common_hidden(a: Recording, b: Recording, slots: list[int] | tuple[int, ...]) -> np.ndarray:
    """Frames where every slot in ``slots`` exists and is hidden in both clips (sorted)."""
    hid = np.ones(len(a), dtype=bool)
    for rec in (a, b):
        for s in slots:
            hid &= rec.exists[:, s] & ~rec.present[:, s]
    return np.flatnonzero(hid)


def middle_splice(hidden: np.ndarray, what: str, k: int = SPLICE_K) -> int:
    """The splice frame in the middle of the first run of ``hidden`` frames that has room for
    ``k`` hidden frames on each side (the largest ``T_k`` the run allows).

    Raises:
        ValueError: no such frame; the concept's ranges hide the objects too briefly.
    """
    cand = splice_frames(hidden, k)
    if cand.size == 0:
        raise ValueError(f"{what}: hidden for too few frames ({hidden.size}) for a splice with {k} "
                         "hidden frames on each side; widen the screen in spec.yaml")
    run = cand[: int(np.argmax(np.diff(np.append(cand, -9)) != 1)) + 1]  # first contiguous run
    return int(run[len(run) // 2])
