"""Frozen descriptions of a 2D side-view scene: dynamic bodies, static segments, screens.

Why: a concept samples a ``Scene`` (pure data, hashable, JSON-able), and ``voe.sim.world`` turns
it into a pymunk space. Keeping the description separate from the engine lets clips store their
static geometry and occluders next to their frames, and lets models (the physics oracle) rebuild
the scene from what is stored.

Units: scene units (metres-like), y up, angles in radians counter-clockwise. The visible window is
``[0, extent[0]] x [0, extent[1]]``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Literal

#: Per-slot state features, in order. Shape/size attributes are constant for an object.
FEATURE_NAMES: tuple[str, ...] = (
    "x", "y", "angle", "vx", "vy", "omega", "is_circle", "is_box", "width", "height", "intensity",
)
N_FEATURES = len(FEATURE_NAMES)

ShapeKind = Literal["circle", "box"]


@dataclass(frozen=True)
class Body:
    """A dynamic object. ``width == height == 2 r`` for circles.

    ``slot`` is the object's stable identity: its row in the ``states`` array.
    """

    slot: int
    shape: ShapeKind
    width: float
    height: float
    x: float
    y: float
    angle: float = 0.0
    vx: float = 0.0
    vy: float = 0.0
    omega: float = 0.0
    mass: float = 1.0
    friction: float = 0.0
    elasticity: float = 0.5
    intensity: float = 0.9

    @property
    def radius(self) -> float:
        return 0.5 * self.width

    def moved(self, **changes: Any) -> Body:
        """A copy with some fields changed (dataclass ``replace``)."""
        return replace(self, **changes)


@dataclass(frozen=True)
class Segment:
    """A static capsule segment: floor, wall, ramp or shelf."""

    a: tuple[float, float]
    b: tuple[float, float]
    radius: float = 0.1
    friction: float = 0.0
    elasticity: float = 0.5
    kind: str = "floor"


@dataclass(frozen=True)
class Occluder:
    """An opaque axis-aligned screen drawn in front of everything; it does not collide."""

    x0: float
    y0: float
    x1: float
    y1: float

    def contains_box(self, lo: tuple[float, float], hi: tuple[float, float], margin: float = 0.0) -> bool:
        """True if the axis-aligned box ``lo..hi`` lies behind this screen, ``margin`` inside its edges.

        The renderer anti-aliases the screen's edges, so a box closer than a pixel to an edge can
        still tint that edge's pixels; callers pass one pixel as ``margin``.
        """
        m = margin
        return (self.x0 + m <= lo[0] and hi[0] <= self.x1 - m
                and self.y0 + m <= lo[1] and hi[1] <= self.y1 - m)


@dataclass(frozen=True)
class Scene:
    """Everything needed to simulate and render a clip's initial state."""

    bodies: tuple[Body, ...]
    statics: tuple[Segment, ...] = ()
    occluders: tuple[Occluder, ...] = ()
    gravity: tuple[float, float] = (0.0, -9.81)
    extent: tuple[float, float] = (10.0, 10.0)

    def geometry(self) -> dict[str, Any]:
        """JSON-able static geometry and occluders, stored with every clip."""
        return {
            "extent": list(self.extent),
            "gravity": list(self.gravity),
            "statics": [dict(vars(s)) for s in self.statics],  # shallow: fields are immutable
            "occluders": [dict(vars(o)) for o in self.occluders],
        }

    def with_bodies(self, bodies: tuple[Body, ...]) -> Scene:
        return replace(self, bodies=tuple(bodies))


def geometry_from_dict(d: dict[str, Any]) -> tuple[tuple[Segment, ...], tuple[Occluder, ...]]:
    """Inverse of ``Scene.geometry`` for the statics and occluders."""
    statics = tuple(
        Segment(a=tuple(s["a"]), b=tuple(s["b"]), radius=s["radius"], friction=s["friction"],
                elasticity=s["elasticity"], kind=s.get("kind", "floor"))
        for s in d.get("statics", [])
    )
    occluders = tuple(Occluder(**o) for o in d.get("occluders", []))
    return statics, occluders


@dataclass(frozen=True)
class SimConfig:
    """Time and image settings shared by every clip of a probe or training set.

    Attributes:
        dt: seconds between stored frames.
        substeps: physics steps per frame (fixed, for determinism and stable contacts).
        n_frames: frames per clip (T).
        size: rendered frame side in pixels (H = W).
        n_slots: object slots per clip (K).
    """

    dt: float = 0.05
    substeps: int = 10
    n_frames: int = 40
    size: int = 64
    n_slots: int = 4
