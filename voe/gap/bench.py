"""Benchmark on concealed effects: random scene, random effect (or none) of random strength.

Why: the finder's claims (right effect, no false discoveries on clean data, real error
reduction) can only be checked where the truth is known. Each case simulates recordings of a
random arena scene (a ball thrown at a box that slides on the ground) with one hidden effect
from the library, adds Gaussian noise, and runs the finder without telling it which effect.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from voe.gap.effects import EFFECTS
from voe.gap.finder import GapConfig, GapFinder
from voe.gap.recordings import Episode
from voe.gap.synth import simulate_episode
from voe.parallel import parallel_map
from voe.sim.scenefile import BodySpec, SceneSpec, StaticSpec

TRUTHS = ("none", "linear_drag", "quadratic_drag", "rolling_resistance", "constant_acceleration",
          "point_attractor", "restitution", "friction", "angular_damping", "spring_anchor", "mass")


@dataclass(frozen=True)
class Case:
    """One bench case: scene, hidden effect name and parameters, and its recordings."""

    scene: SceneSpec
    truth: str
    params: np.ndarray
    bodies: tuple[str, ...] | None
    episodes: list[Episode]


def random_scene(rng: np.random.Generator) -> SceneSpec:
    """Ground and two walls; a ball and a box with random materials."""
    e_ball, e_box = rng.uniform(0.5, 0.8), rng.uniform(0.2, 0.4)
    fr = rng.uniform(0.4, 0.7)
    bodies = (BodySpec("ball", "circle", mass=float(rng.uniform(0.5, 1.5)), radius=float(rng.uniform(0.08, 0.15)),
                       friction=fr, elasticity=e_ball),
              BodySpec("box", "box", mass=float(rng.uniform(1.0, 3.0)), size=(0.3, 0.2), friction=fr, elasticity=e_box))
    statics = (StaticSpec((-8.0, 0.0), (8.0, 0.0), 0.0, 1.0, 1.0),
               StaticSpec((-8.0, 0.0), (-8.0, 5.0), 0.0, 1.0, 1.0),
               StaticSpec((8.0, 0.0), (8.0, 5.0), 0.0, 1.0, 1.0))
    return SceneSpec((0.0, -9.81), bodies, statics, ())


def random_effect(name: str, scene: SceneSpec, rng: np.random.Generator) -> tuple[np.ndarray, tuple[str, ...] | None]:
    """A random strength (and position) for the hidden effect, strong enough to matter."""
    ball, box = scene.bodies
    if name == "linear_drag":
        return np.array([rng.uniform(0.15, 0.5)]), None
    if name == "quadratic_drag":
        return np.array([rng.uniform(0.05, 0.2)]), None
    if name == "rolling_resistance":
        return np.array([rng.uniform(0.03, 0.1)]), None
    if name == "constant_acceleration":
        a = rng.uniform(0.3, 1.0)
        th = rng.uniform(0, 2 * np.pi)
        return np.array([a * np.cos(th), a * np.sin(th)]), None
    if name == "point_attractor":
        return np.array([rng.uniform(0.5, 2.0), rng.uniform(-2, 2), rng.uniform(0.5, 2.0)]), None
    if name == "spring_anchor":
        return np.array([rng.uniform(0.3, 1.0), rng.uniform(-2, 2), rng.uniform(0.0, 2.0)]), None
    if name == "restitution":
        e = np.mean([ball.elasticity, box.elasticity])
        return np.array([np.clip(e + rng.choice([-1, 1]) * rng.uniform(0.2, 0.3), 0.05, 0.95)]), None
    if name == "friction":
        return np.array([rng.choice([rng.uniform(0.1, 0.2), rng.uniform(1.1, 1.5)])]), None
    if name == "angular_damping":
        return np.array([rng.uniform(0.3, 1.0) * ball.moment_value() * 3]), None
    if name == "mass":
        return np.array([rng.choice([rng.uniform(0.3, 0.5), rng.uniform(2.0, 3.0)])]), ("box",)
    return np.zeros(0), None


def ball_box_gap(scene: SceneSpec, pose: np.ndarray) -> np.ndarray:
    """(T,) distance in metres between the ball's surface and the box, from poses (T, B, 3),
    ball first, box second (negative when they overlap)."""
    ball, box = scene.bodies
    d = pose[:, 0, :2] - pose[:, 1, :2]  # (T, 2) ball relative to box, world frame
    c, s = np.cos(pose[:, 1, 2]), np.sin(pose[:, 1, 2])
    local = np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1)  # box frame
    half = np.asarray(box.size) / 2
    return np.linalg.norm(local - np.clip(local, -half, half), axis=1) - ball.radius


def ball_hits_box(scene: SceneSpec, t: np.ndarray, pose: np.ndarray, tol: float = 5e-3, min_speed: float = 1.0) -> bool:
    """Whether the ball strikes the box (touches it closing at >= ``min_speed`` m/s) in clean
    poses (T, B, 3), ball first, box second."""
    gap = ball_box_gap(scene, pose)  # (T,)
    closing = -np.gradient(gap, t)  # (T,) m/s
    before = np.concatenate([[False], gap[1:] < tol]) & (np.concatenate([[np.inf], gap[:-1]]) >= tol)
    return bool(np.any(before & (np.roll(closing, 1) >= min_speed)))


def make_case(rng: np.random.Generator, truth: str, noise: float = 1e-3, episodes: int = 12,
              duration: float = 3.0, rate: float = 100.0, tries: int = 40) -> Case:
    """Simulate ``episodes`` recordings with the hidden ``truth`` effect.

    Every episode is drawn so that the ball strikes the box, closing at 1 m/s or more (up to
    ``tries`` throws, judged on the clean simulation *with* the hidden effect, for every truth
    alike, ``none`` included). Why: a
    concealed effect that never acts is not a test. A body's mass only changes a trajectory
    through collisions with other bodies (with gravity and Coulomb friction alone every body
    falls and slides the same whatever its mass), and with free throws the ball missed the box
    in most episodes (or rolled into it at walking pace), so ``mass`` was unidentifiable by
    construction. Twelve episodes (the finder holds out the last four) give about ten held-out
    windows with at least four strikes among them, so a gain carried by collision windows
    survives the finder's bootstrap over held-out windows.
    """
    scene = random_scene(rng)
    params, bodies = random_effect(truth, scene, rng)
    effect = EFFECTS.get(truth)(bodies=bodies)
    t = np.arange(int(round(duration * rate)) + 1) / rate
    sigma = np.array([[noise, noise, 10 * noise]] * len(scene.bodies))  # (B, 3)
    clean_noise = np.zeros_like(sigma)
    eps = []
    for k in range(episodes):
        for _ in range(tries):
            xb = rng.uniform(-0.5, 1.0)
            pose0 = np.array([[xb - rng.uniform(1.5, 3.0), rng.uniform(0.3, 1.2), 0.0],
                              [xb, 0.1, 0.0]])  # (B, 3)
            vel0 = np.array([[rng.uniform(2.0, 4.0), rng.uniform(0.5, 3.0), rng.uniform(-15, 15)],
                             [rng.uniform(-1.5, 1.5), 0.0, 0.0]])
            clean = simulate_episode(scene, k, t, pose0, vel0, effect, params, clean_noise, rng)
            if ball_hits_box(scene, t, clean.pose):
                break
        eps.append(Episode(k, t.copy(), clean.pose + rng.normal(size=clean.pose.shape) * sigma[None]))
    return Case(scene, truth, params, bodies, eps)


def param_error(truth: str, true_p: np.ndarray, found: dict, true_bodies: tuple[str, ...] | None = None) -> float:
    """Relative error of the hidden effect's parameters (vector norm ratio).

    In the two-body bench scene only the ratio of the masses shows (they meet only in
    ball-box collisions, and gravity and friction do not depend on mass), so the finder reports
    ``mass[ball]`` and ``mass[box]`` as one group; a ball scale s is compared as a box scale 1/s.
    """
    est = np.array(list(found["params"].values()))
    if true_p.size == 0 or est.shape != true_p.shape:
        return float("nan")
    if truth == "mass" and true_bodies and set(found["bodies"]) != set(true_bodies):
        est = 1.0 / est
    return float(np.linalg.norm(est - true_p) / max(np.linalg.norm(true_p), 1e-12))


def run_case(args: tuple) -> dict:
    """Make and diagnose one case ``(seed, truth, noise, max_effects[, episodes, duration])``;
    returns truth, identified name and numbers."""
    seed, truth, noise, max_effects, *shape = args
    rng = np.random.default_rng(seed)
    case = make_case(rng, truth, noise, *shape)
    try:
        finder = GapFinder(max_effects=max_effects, seed=seed, config=GapConfig()).fit(case.scene, case.episodes)
    except Exception as exc:  # a crash is a failed case, reported, not a lost bench
        return {"seed": seed, "truth": truth, "found": f"error: {type(exc).__name__}", "group": [], "n_effects": 1,
                "before": float("nan"), "after": float("nan"), "param_error": float("nan")}
    found = finder.effects_[0]["name"] if finder.effects_ else "none"
    group = finder.groups_[0] if finder.groups_ else []
    out = {"seed": seed, "truth": truth, "found": found, "group": group, "n_effects": len(finder.effects_),
           "before": finder.fit_["before"], "after": finder.fit_["after"], "param_error": float("nan")}
    if finder.effects_ and found == truth:
        out["param_error"] = param_error(truth, case.params, finder.effects_[0], case.bodies)
    return out


MIN_CLEAN = 20  # clean cases a default run includes, so the false-discovery rate means something


def plan(cases: int, seed: int = 0, clean: int | None = None,
         truths: tuple[str, ...] = TRUTHS) -> list[tuple[int, str]]:
    """(case seed, truth) pairs: ``cases`` cycling through ``truths`` (``none`` included), then
    ``clean`` extra ``none`` cases (default: enough for ``MIN_CLEAN`` clean cases in all)."""
    todo = [(seed * 1000 + i, truths[i % len(truths)]) for i in range(cases)]
    n_clean = sum(t == "none" for _, t in todo)
    extra = max(0, MIN_CLEAN - n_clean) if clean is None else clean
    return todo + [(seed * 1000 + cases + i, "none") for i in range(extra)]


def run_bench(cases: int = 22, noise: float = 1e-3, seed: int = 0, jobs: int = 1, max_effects: int = 3,
              progress: Callable[[dict], None] | None = None, clean: int | None = None,
              truths: tuple[str, ...] = TRUTHS, episodes: int = 12, duration: float = 3.0) -> list[dict]:
    """Run ``cases`` cases cycling through every truth (``none`` included), plus extra clean
    cases (see ``plan``); each case has ``episodes`` recordings of ``duration`` seconds."""
    todo = [(s, t, noise, max_effects, episodes, duration) for s, t in plan(cases, seed, clean, truths)]
    results: list[dict] = []
    for r in parallel_map(run_case, todo, jobs):
        results.append({**r, "extra": len(results) >= cases})
        if progress:
            progress(results[-1])
    return results


def clopper_pearson(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Exact (Clopper-Pearson) two-sided confidence interval of a binomial proportion k/n."""
    from scipy.stats import beta

    if n == 0:
        return 0.0, 1.0
    a = (1 - level) / 2
    lo = 0.0 if k == 0 else float(beta.ppf(a, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(1 - a, k + 1, n - k))
    return lo, hi


def summary_lines(results: list[dict], noise: float) -> list[str]:
    """The printed bench report: confusion matrix, accuracy, false discovery, recovery, RMSE cut."""
    names = list(TRUTHS)
    found_names = sorted({r["found"] for r in results} | set(names), key=lambda n: (n not in names, names.index(n) if n in names else 0))
    short = {n: n[:6] for n in found_names}
    lines = [f"gap bench: {len(results)} cases ({sum(not r.get('extra') for r in results)} cycling through "
             f"the truths + {sum(bool(r.get('extra')) for r in results)} extra clean), noise {noise * 1e3:g} mm, 100 Hz",
             "confusion (rows true, cols identified): " + " ".join(f"{short[n]:>6}" for n in found_names)]
    for t in names:
        row = [sum(1 for r in results if r["truth"] == t and r["found"] == f) for f in found_names]
        if sum(row):
            lines.append(f"  {t:>22} " + " ".join(f"{c:>6d}" for c in row))
    cycle = [r for r in results if not r.get("extra")]  # the balanced cycle over all truths
    correct = sum(r["truth"] == r["found"] for r in cycle)
    effects = [r for r in cycle if r["truth"] != "none"]
    correct_eff = sum(r["truth"] == r["found"] for r in effects)
    clean = [r for r in results if r["truth"] == "none"]
    n_false = sum(r["n_effects"] > 0 for r in clean)
    fdr = n_false / max(1, len(clean))
    _, fdr_hi = clopper_pearson(n_false, len(clean))
    acc_lo, acc_hi = clopper_pearson(correct, len(cycle))
    ident = [r for r in results if r["truth"] != "none" and r["found"] == r["truth"]]
    cut = [1 - r["after"] / r["before"] for r in ident if r["before"] > 0]
    perr = [r["param_error"] for r in ident if np.isfinite(r["param_error"])]
    in_group = sum(r["truth"] == r["found"] or r["truth"] in r["group"] for r in results if r["truth"] != "none")
    lines += [f"correct identification: {correct}/{len(cycle)} = {100 * correct / max(1, len(cycle)):.0f} % "
              f"(95 % CI {100 * acc_lo:.0f}-{100 * acc_hi:.0f} %; target >= 90 %; balanced cycle over all truths, "
              f"extra clean cases not counted)",
              f"correct identification where an effect is hidden: {correct_eff}/{len(effects)}",
              f"true effect named or in reported group: {in_group}/{sum(r['truth'] != 'none' for r in results)}",
              f"false discovery on clean: {n_false}/{len(clean)} = {100 * fdr:.1f} % "
              f"(95 % Clopper-Pearson upper bound {100 * fdr_hi:.1f} %; target <= 5 %)",
              f"parameter recovery error (median relative): {100 * np.median(perr) if perr else float('nan'):.1f} %",
              f"median held-out RMSE reduction when identified: {100 * np.median(cut) if cut else float('nan'):.0f} % (target >= 80 %)"]
    return lines
