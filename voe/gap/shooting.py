"""Multiple shooting: re-initialise the simulator from the recordings at the start of each window.

Why: a long free rollout of a scene with collisions diverges from any recording (chaos), so the
residual would say nothing about *where* the physics is wrong. Short windows that restart from
the recorded pose, with a velocity estimated from a local quadratic fit, keep the residual small
wherever the model is right. The noise floor comes from the data itself (fourth differences), and
the expected residual of a correct model grows inside a window as the initial-velocity error
integrates; ``sigma_pred`` gives that growth so residuals can be turned into z-scores.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from voe.gap.bare import Bare
from voe.gap.effects.base import Effect
from voe.gap.recordings import Episode
from voe.gap.rollout import run_many
from voe.sim.scenefile import SceneSpec

HALF = 7  # samples on each side for the velocity fit
ORDER = 3  # cubic: a quadratic biases the speed of a fast pendulum by ~2 %


@dataclass(frozen=True)
class Window:
    """Samples ``k0 .. k1`` (inclusive) of episode number ``ep`` (index into the episode list)."""

    ep: int
    k0: int
    k1: int


def local_state(ep: Episode, k: int, half: int | None = None, substep: float = 0.0) -> tuple[np.ndarray, np.ndarray, float]:
    """Smoothed pose and velocity at sample ``k`` from a local cubic fit; with ``substep``, the
    velocity the simulator must start from to follow the fitted path (the fit's velocity plus half
    a substep of its acceleration).

    Why the half step: pymunk (Chipmunk) moves each body with the velocity it had before the
    step's velocity update, so over a stretch of constant acceleration a its positions run
    x0 + v t + a t^2 / 2 - a dt t / 2, and the velocity read off positions is the simulator's
    own minus a dt / 2. A window restarted from the velocity read off positions drifted by
    a dt / 2 per second: 4.9 mm per second of window in flight at 1 ms substeps, with no noise
    and no missing physics (docs/bench-runs/dev-s60/halfstep.py), enough to turn a knife-edge
    impact the other way (development case 4497026, episode 7: restarted from the noise-free
    state before t = 0.2 s the ball missed by 120-215 mm; with the half step, by 0.01 mm). A real,
    continuous recording gives the continuous velocity, and the simulator started from it drifts
    by the same amount, so the correction is the same.

    Returns:
        pose (B, 3), vel (B, 3), and the sum of squared time offsets used (for the velocity
        error: var(v) ~ sigma^2 / sum dt^2).
    """
    half = HALF if half is None else half
    n = min(len(ep.t), max(2 * half + 1, ORDER + 3))  # one-sided at the ends, never too few samples
    lo = min(max(0, k - n // 2), len(ep.t) - n)
    hi = lo + n
    tt = ep.t[lo:hi] - ep.t[k]  # (N,)
    y = ep.pose[lo:hi].reshape(hi - lo, -1)  # (N, B*3)
    span = max(float(np.max(np.abs(tt))), 1e-9)  # scale time to [-1, 1] so the fit is well conditioned
    coef = np.polyfit(tt / span, y, ORDER)  # (ORDER+1, B*3)
    b = ep.pose.shape[1]
    sxx = float(np.sum((tt - tt.mean()) ** 2))
    vel = coef[-2].reshape(b, 3) / span + 0.5 * substep * (2.0 * coef[-3].reshape(b, 3) / span**2)  # (B, 3)
    return coef[-1].reshape(b, 3), vel, sxx


def noise_floor(episodes: list[Episode]) -> np.ndarray:
    """(B, 3) robust per-body, per-variable noise sigma (see ``noise_model``)."""
    return noise_model(episodes)[0]


_PHI = np.linspace(0.0, 0.95, 96)
_STRIDES = (1, 2, 3, 4)


def d4_var(phi: np.ndarray) -> np.ndarray:
    """Variance of the fourth difference of unit-variance AR(1) noise with coefficient ``phi``."""
    return 70 - 112 * phi + 56 * phi**2 - 16 * phi**3 + 2 * phi**4


def noise_model(episodes: list[Episode]) -> tuple[np.ndarray, np.ndarray]:
    """(B, 3) noise sigma and (B, 3) AR(1) coefficient phi, from fourth differences at strides 1-4.

    White noise of sigma gives a fourth difference of variance 70 sigma^2 at every stride.
    AR(1) (coloured) noise of coefficient phi is, at stride s, AR(1) of coefficient phi^s, so its
    d4 variance grows with the stride in a known way; smooth motion adds a part growing like
    s^8. Per body and variable, (sigma^2, signal) are fitted by least squares for every phi on a
    grid and the best phi kept. The coloured model is used only when it is clear (phi > 0.3 and
    the signal part small at stride 1); otherwise the white estimate (stride-1 variance / 70),
    which is what a signal-dominated recording such as an encoder gets. Robust (MAD) variances
    ignore impacts. Why: the null replicate must carry the data's own noise, white or not; a
    white null under coloured noise mistakes slow noise wander for missing physics.
    """
    var = []
    for s in _STRIDES:
        d4 = np.concatenate([np.diff(e.pose[::s], n=4, axis=0) for e in episodes if len(e.t) > 4 * s + 1], axis=0)
        mad = 1.4826 * np.median(np.abs(d4 - np.median(d4, axis=0)), axis=0)  # (B, 3)
        var.append(mad**2)
    v = np.stack(var)  # (S, B, 3)
    white = np.sqrt(v[0] / 70.0)
    sig2 = np.asarray(_STRIDES, float) ** 8
    sigma, phi = white.copy(), np.zeros_like(white)
    for b, k in np.ndindex(white.shape):
        y = v[:, b, k]
        if y[0] <= 0:
            continue
        best = (np.inf, 0.0, 0.0, 0.0)
        for ph in _PHI:
            a = np.stack([d4_var(ph ** np.asarray(_STRIDES, float)), sig2], axis=1)  # (S, 2)
            coef, *_ = np.linalg.lstsq(a / y[:, None], np.ones_like(y), rcond=None)  # relative errors
            coef = np.maximum(coef, 0.0)
            err = float(np.sum((a @ coef / y - 1.0) ** 2))
            if err < best[0]:
                best = (err, ph, coef[0], coef[1])
        _, ph, s2, sig = best
        if ph > 0.3 and sig < 0.2 * s2 * d4_var(ph) and s2 > 0:
            sigma[b, k], phi[b, k] = np.sqrt(s2), ph
    return np.maximum(sigma, 1e-7), phi


def make_windows(episodes: list[Episode], which: list[int], length: float, stride: float | None = None,
                 bad_start: dict[int, np.ndarray] | None = None) -> list[Window]:
    """Cut episodes ``which`` into windows of ``length`` seconds (last partial window dropped).

    Args:
        bad_start: per episode index, (T,) bool of samples a window must not start at (near an
            impact the velocity fit straddles the bounce and the initial state is garbage);
            such windows are moved forward to the next clean sample.
    """
    stride = stride or length
    out = []
    for i in which:
        t = episodes[i].t
        bad = bad_start.get(i) if bad_start else None
        start = t[0]
        while True:
            k0 = int(np.searchsorted(t, start - 1e-9))
            if bad is not None:
                while k0 < len(t) - 1 and bad[k0]:
                    k0 += 1
            k1 = int(np.searchsorted(t, t[min(k0, len(t) - 1)] + length + 1e-9)) - 1
            if k0 >= len(t) - 1 or t[k1] - t[k0] < 0.8 * length:
                break
            out.append(Window(i, k0, k1))
            start = max(start + stride, t[k1] if stride >= length else t[k0] + stride)
    return out


def gyration(scene: SceneSpec) -> np.ndarray:
    """(B,) sqrt(I/m) of each body: the length that turns an angle error into metres."""
    return np.array([b.gyration_radius for b in scene.bodies])


MEMO = 2048  # windows a Shooter remembers (about 5 kB each for 1 s of two bodies at 100 Hz)


def _effect_key(effect: Effect | None, params: np.ndarray | None) -> tuple | None:
    """What a rollout depends on besides the window: each part's class and bodies, and the
    parameters to the bit ((None,) for the nominal scene). None (not remembered) unless every
    part is a library effect (``voe.gap.effects``, whose force laws keep no state between
    calls; the bench's ``Gust`` counts its kicks)."""
    if effect is None:
        return (None,)
    if not all(type(e).__module__.startswith("voe.gap.effects.") for e in effect.parts):
        return None
    p = np.asarray(params, dtype=float)
    return (tuple((type(e), e.bodies) for e in effect.parts), p.shape, p.tobytes())


class Shooter:
    """Simulates windows of recorded episodes under an effect with given parameters.

    Args:
        scene: the nominal scene (joints resolved).
        episodes: the recordings.
        substep: simulator step in seconds.
    """

    def __init__(self, scene: SceneSpec, episodes: list[Episode], substep: float, half: int = HALF) -> None:
        self.scene, self.episodes, self.substep, self.half = scene, episodes, substep, half
        self._ic: dict[tuple[int, int], tuple[np.ndarray, np.ndarray, float]] = {}
        self.scale = np.concatenate([np.ones((len(scene.bodies), 2)), gyration(scene)[:, None]], axis=1)  # (B, 3)
        self.n_rollouts = 0  # windows asked for (one found in the memo counts too: the count does not depend on processes)
        self.n_memo = 0  # of which taken from the memo
        self._memo: OrderedDict[tuple, np.ndarray] = OrderedDict()
        self.bare = Bare()  # windows a region material cannot touch (voe.gap.bare)

    def initial(self, ep: int, k: int) -> tuple[np.ndarray, np.ndarray, float]:
        key = (ep, k)
        if key not in self._ic:
            self._ic[key] = local_state(self.episodes[ep], k, self.half, self.substep)
        return self._ic[key]

    def simulate(self, win: Window, effect: Effect | None, params: np.ndarray | None) -> np.ndarray:
        """Predicted poses (n, B, 3) over the window's samples."""
        return self.simulate_many([win], effect, params)[0]

    def simulate_many(self, wins: list[Window], effect: Effect | None, params: np.ndarray | None) -> list[np.ndarray]:
        """Predicted poses (n_i, B, 3) of every window, simulated side by side (``run_many``);
        each is the same as ``simulate`` gives it alone.

        A window simulated before under the same effect (classes and bodies of its parts) and
        the same parameter vector (to the bit) is taken from a memo of the last ``MEMO`` windows
        (a copy): the simulation is deterministic and a window's poses do not depend on the
        windows simulated beside it, so the poses are the same. Why: the same windows come back
        under the same model (the nominal model at several stages, a fit's start point, a
        line search that evaluates its current point again); about 3 % of the rollouts of
        ``bench/gap_speed.py``.
        """
        self.n_rollouts += len(wins)
        key = _effect_key(effect, params)
        keys = [(key, w.ep, w.k0, w.k1) for w in wins]
        memo = self._memo if key is not None else {}
        out: list[np.ndarray | None] = [None] * len(wins)
        todo = []
        for i, k in enumerate(keys):
            hit = memo.get(k)
            if hit is None:
                todo.append(i)
            else:
                memo.move_to_end(k)
                out[i] = hit.copy()
                self.n_memo += 1
        if todo:
            for i, pose in zip(todo, self.bare.simulate(self, [wins[i] for i in todo], effect, params, key),
                               strict=True):
                out[i] = pose
                if key is not None:
                    memo[keys[i]] = pose.copy()
            while len(self._memo) > MEMO:
                self._memo.popitem(last=False)
        return out  # type: ignore[return-value]

    def starts_times(self, wins: list[Window]) -> tuple[list[tuple[np.ndarray, np.ndarray]], list[np.ndarray]]:
        """Each window's start (pose (B, 3), velocity (B, 3)) and sample times (n_i,)."""
        return ([self.initial(w.ep, w.k0)[:2] for w in wins],  # type: ignore[misc]
                [self.episodes[w.ep].t[w.k0:w.k1 + 1] for w in wins])

    def run(self, wins: list[Window], effect: Effect | None, params: np.ndarray | None) -> list[np.ndarray]:
        """Poses (n_i, B, 3) of every window, all simulated (no memo)."""
        return run_many(self.scene, *self.starts_times(wins), self.substep, effect, params)

    def residual(self, win: Window, effect: Effect | None, params: np.ndarray | None) -> np.ndarray:
        """Prediction minus recording, (n, B, 3), angle converted to metres by sqrt(I/m)."""
        return self.residuals([win], effect, params)[0]

    def residuals(self, wins: list[Window], effect: Effect | None, params: np.ndarray | None) -> list[np.ndarray]:
        """``residual`` of every window, simulated side by side."""
        preds = self.simulate_many(wins, effect, params)
        return [(pred - self.episodes[w.ep].pose[w.k0:w.k1 + 1]) * self.scale[None]
                for w, pred in zip(wins, preds, strict=True)]

    def sigma_pred(self, win: Window, sigma: np.ndarray) -> np.ndarray:
        """(n, B, 3) expected |residual| of a correct model: noise plus integrated velocity error."""
        ep = self.episodes[win.ep]
        _, _, sxx = self.initial(win.ep, win.k0)
        tau = ep.t[win.k0:win.k1 + 1] - ep.t[win.k0]  # (n,)
        s = sigma * self.scale  # (B, 3)
        var = s[None] ** 2 * (1.25 + tau[:, None, None] ** 2 / max(sxx, 1e-12))
        return np.sqrt(var)


def rmse(res: list[np.ndarray]) -> float:
    """Root mean square over all windows, bodies and the three pose-equivalent coordinates."""
    if not res:
        return float("nan")
    return float(np.sqrt(np.mean(np.concatenate([r.reshape(-1) for r in res]) ** 2)))


def position_rmse(res: list[np.ndarray]) -> float:
    """Root mean square of the x, y residuals only, in metres."""
    return float(np.sqrt(np.mean(np.concatenate([r[..., :2].reshape(-1) for r in res]) ** 2)))


def choose_half(scene: SceneSpec, episodes: list[Episode], windows: list[Window], substep: float,
                options: tuple[int, ...] = (2, 3, 5, 8, 12)) -> int:
    """The velocity-fit half-width that lets the nominal model follow the data best.

    Why: a wide fit averages noise away but biases the speed of fast, curving motion; on clean
    encoder data +-2 samples is best, on 1 mm noise about +-8. The median window RMSE of the
    nominal model over the first 10 samples after each window start picks the trade-off from the
    data itself; the horizon is short so a missing effect (which grows like t^2) cannot bias the
    choice toward a velocity fit that mimics it.
    """
    sample = [Window(w.ep, w.k0, min(w.k1, w.k0 + 10)) for w in windows[:: max(1, len(windows) // 40)]]
    scores = []
    for h in options:
        sh = Shooter(scene, episodes, substep, h)
        scores.append(float(np.median([np.sqrt(np.mean(r**2)) for r in sh.residuals(sample, None, None)])))
    return options[int(np.argmin(scores))]


def window_score(res: list[np.ndarray]) -> float:
    """Median over windows of each window's RMSE: the robust held-out score.

    Why: a few windows with collisions are chaotic; their residuals swing wildly with any change
    of the model and would let a flexible effect "win" on clean data by luck.
    """
    return float(np.median([np.sqrt(np.mean(r**2)) for r in res])) if res else float("nan")


def window_sse(shooter: Shooter, wins: list[Window], effect: Effect | None, params: np.ndarray | None) -> np.ndarray:
    """(W,) sum of squared residuals of each window (``Shooter.residuals``)."""
    return np.array([float(np.sum(r**2)) for r in shooter.residuals(wins, effect, params)])
