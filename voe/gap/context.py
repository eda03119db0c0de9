"""Label what each body is doing in each recorded frame: flight, impact, rolling, sliding, swinging.

Why: "the model is wrong from t = 1.2 s" helps less than "the model is wrong whenever the ball is
rolling". Labels come from the recordings alone (geometry against the static segments, rolling
condition v = -omega r, acceleration spikes), so they do not depend on any model.
"""

from __future__ import annotations

import numpy as np

from voe.gap.recordings import Episode
from voe.sim.scenefile import SceneSpec

LABELS = ("flight", "impact", "rolling", "sliding", "swinging")


def _outline(scene: SceneSpec, b: int, pose: np.ndarray) -> np.ndarray:
    """(T, V, 2) world outline points of body ``b`` over poses (T, 3)."""
    local = scene.bodies[b].local_vertices()  # (V, 2)
    c, s = np.cos(pose[:, 2])[:, None], np.sin(pose[:, 2])[:, None]
    x = pose[:, :1] + c * local[None, :, 0] - s * local[None, :, 1]
    y = pose[:, 1:2] + s * local[None, :, 0] + c * local[None, :, 1]
    return np.stack([x, y], axis=-1)


def _gap_to_statics(scene: SceneSpec, pts: np.ndarray) -> np.ndarray:
    """(T,) smallest distance from any outline point (T, V, 2) to any static segment surface."""
    best = np.full(pts.shape[0], np.inf)
    for st in scene.statics:
        a, b = np.asarray(st.a), np.asarray(st.b)
        ab = b - a
        u = np.clip(((pts - a) @ ab) / max(float(ab @ ab), 1e-12), 0, 1)  # (T, V)
        d = np.linalg.norm(pts - (a + u[..., None] * ab), axis=-1) - st.radius
        best = np.minimum(best, d.min(axis=1))
    return best


def spike_level(acc: np.ndarray, g: float) -> float:
    """Acceleration magnitude (m/s^2) above which a sample (T, 2) is an impact spike: 3 g, or
    well above the noise of twice-differenced positions if that is larger.

    Why: with 3 mm of noise (or timestamps 2 ms off) the second differences of positions at
    100 Hz scatter by about 2 g, so a fixed 3 g marked a quarter of all samples as impacts, every
    window start was refused, and the finder had no window left. The noise is measured on the
    recording itself (median absolute deviation, which the few real impact samples barely move).
    """
    dev = acc - np.median(acc, axis=0)
    s = 1.4826 * np.median(np.abs(dev), axis=0)  # (2,) robust sd per axis
    return float(max(3 * g, 4 * np.sqrt(np.sum(s**2))))


def frame_labels(scene: SceneSpec, ep: Episode, tol: float = 0.004) -> np.ndarray:
    """(T, B) array of labels from ``LABELS`` for every frame and body."""
    t_len, n_b, _ = ep.pose.shape
    out = np.empty((t_len, n_b), dtype=object)
    jointed = scene.jointed()
    dt = np.gradient(ep.t)  # (T,)
    vel = np.gradient(ep.pose, axis=0) / dt[:, None, None]  # (T, B, 3)
    acc = np.gradient(vel, axis=0) / dt[:, None, None]
    g = float(np.linalg.norm(scene.gravity)) or 9.81
    for b in range(n_b):
        if jointed[b]:
            out[:, b] = "swinging"
            continue
        touching = _gap_to_statics(scene, _outline(scene, b, ep.pose[:, b])) < tol if scene.statics else np.zeros(t_len, bool)
        spike = np.linalg.norm(acc[:, b, :2], axis=1) > spike_level(acc[:, b, :2], g)
        onset = np.zeros(t_len, bool)
        onset[1:] = touching[1:] & ~touching[:-1]
        impact = np.convolve((spike | onset).astype(float), np.ones(5), mode="same") > 0
        spec = scene.bodies[b]
        speed = np.linalg.norm(vel[:, b, :2], axis=1)
        if spec.shape == "circle":
            slip = np.abs(vel[:, b, 0] + vel[:, b, 2] * spec.radius)  # ground contact below the COM
            rolling = slip < 0.1 * speed + 0.02
        else:
            rolling = np.zeros(t_len, bool)
        lab = np.where(touching, np.where(rolling, "rolling", "sliding"), "flight").astype(object)
        lab[impact] = "impact"
        out[:, b] = lab
    return out


def summarize(labels: np.ndarray, pose: np.ndarray) -> tuple[str, list[float]]:
    """Dominant label of a stretch (T,) and its region [xmin, xmax, ymin, ymax].

    Impacts win if present (they are brief but decisive); a stretch with no label covering 60 %
    of its frames is described by its region of space instead.
    """
    region = [float(pose[:, 0].min()), float(pose[:, 0].max()), float(pose[:, 1].min()), float(pose[:, 1].max())]
    vals, counts = np.unique(labels.astype(str), return_counts=True)
    if "impact" in vals:
        return "impact", region
    top = vals[np.argmax(counts)]
    if counts.max() < 0.6 * len(labels):
        return f"region x {region[0]:.2f}..{region[1]:.2f} m, y {region[2]:.2f}..{region[3]:.2f} m", region
    return str(top), region


def near_contact(scene: SceneSpec, ep: Episode, tol: float = 0.01) -> np.ndarray:
    """(T,) bool: two bodies not joined to each other are within ``tol`` of touching (bounding
    circles), at any sample of ``ep``.

    Why: a window that starts inside a collision between bodies (two riders on an air track)
    estimates both start velocities across the impact, and every model then sends the bodies
    on through each other; such windows must not start there.
    """
    return near_bodies(scene, ep, tol).any(axis=1)


def near_bodies(scene: SceneSpec, ep: Episode, tol: float = 0.01) -> np.ndarray:
    """(T, B) bool: body b is within ``tol`` of touching another body not joined to it
    (bounding circles).

    Why per body: ``frame_labels`` looks only at statics, so a ball resting on top of a box is
    labelled ``flight``; its recorded acceleration there is zero, not gravity, and must not be
    read as a missing force (``voe.gap.prefit.flight_samples``).
    """
    reach = np.array([float(np.max(np.linalg.norm(b.local_vertices(), axis=1))) for b in scene.bodies])  # (B,)
    joined = {frozenset((j.a, j.b)) for j in scene.joints if j.b is not None}
    names = scene.names
    out = np.zeros((len(ep.t), len(names)), dtype=bool)
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            if frozenset((names[i], names[j])) in joined:
                continue
            d = np.linalg.norm(ep.pose[:, i, :2] - ep.pose[:, j, :2], axis=1)  # (T,)
            near = d < reach[i] + reach[j] + tol
            out[:, i] |= near
            out[:, j] |= near
    return out
