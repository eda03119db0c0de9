"""A test window's start velocity refitted under a model (development prototype): Levenberg-Marquardt on the
window's whitened residual with the start fit's own velocity error as a Gaussian prior (a MAP estimate), and the
window z (``voe.gap.locate.window_z``'s statistic) at the refitted start. Used by ``refit_start.py`` and
``deep_tails.py``."""

import numpy as np

from voe.gap.rollout import run_many
from voe.gap.shooting import Shooter


def sigma_v(half: int, dt: float, sigma: np.ndarray) -> np.ndarray:
    """(B, 3) standard error of the centred cubic start fit's velocity (``local_state``) for noise ``sigma``."""
    t = np.arange(-half, half + 1) * dt
    x = np.vander(t, 4)
    return sigma * np.sqrt(np.linalg.inv(x.T @ x)[2, 2])


def z_of(sh: Shooter, w, pred: np.ndarray, sigma: np.ndarray) -> float:
    r = (pred - sh.episodes[w.ep].pose[w.k0:w.k1 + 1]) * sh.scale[None] / sh.sigma_pred(w, sigma)
    return float(np.sqrt(np.mean(r[1:] ** 2, axis=0)).max())


def refit(sh: Shooter, w, effect, params, sigma, sv, iters=10):
    """LM on the start velocity (B*3): whitened residual of the window plus the prior dv / sv."""
    pose0, vel0 = sh.initial(w.ep, w.k0)[:2]
    t = sh.episodes[w.ep].t[w.k0:w.k1 + 1]
    data = sh.episodes[w.ep].pose[w.k0:w.k1 + 1]
    wt = sh.scale[None] / sh.sigma_pred(w, sigma)
    svf = sv.reshape(-1)
    live = svf > 0

    def resid(dv_list):
        starts = [(pose0, vel0 + dv.reshape(vel0.shape)) for dv in dv_list]
        preds = run_many(sh.scene, starts, [t] * len(starts), sh.substep, effect, params)
        return [np.concatenate([((p - data) * wt)[1:].reshape(-1), dv / np.where(live, svf, 1.0)]) for p, dv in
                zip(preds, dv_list, strict=True)], preds

    dv = np.zeros(vel0.size)
    (r,), (pred,) = resid([dv])
    cost, lam = float(r @ r), 1e-2
    for _ in range(iters):
        steps = 0.3 * svf
        trial = [dv] + [dv + np.eye(dv.size)[k] * steps[k] for k in range(dv.size) if live[k]]
        rs, _ = resid(trial)
        idx = np.flatnonzero(live)
        jac = np.stack([(rs[1 + i] - rs[0]) / steps[k] for i, k in enumerate(idx)], axis=1)
        h = jac.T @ jac
        g = jac.T @ rs[0]
        improved = False
        for _ in range(6):
            step = -np.linalg.solve(h + lam * np.diag(np.diag(h) + 1e-12), g)
            cand = dv.copy()
            cand[idx] += step
            (rc,), (pc,) = resid([cand])
            if np.isfinite(rc).all() and float(rc @ rc) < cost:
                dv, cost, pred, lam, improved = cand, float(rc @ rc), pc, lam / 3, True
                break
            lam *= 10
        if not improved:
            break
    return pred, dv.reshape(vel0.shape)



def truth_pairs(seed: int, truth: str, kind: str):
    """A bench case prepared as the finder does, the truth as a fitted model (dev-s62's ``truth_model``) and the
    test windows with the truth's parameters: (case, problem, model, pairs)."""
    from guards_at_truth import truth_model

    from voe.gap.bench import make_case
    from voe.gap.check import heldout_pairs
    from voe.gap.finder import ALL_EFFECTS
    from voe.gap.stages import GapConfig, prepare

    case = make_case(np.random.default_rng(seed), truth, 1e-3, 12, 3.0, noise_kind=kind)
    config = GapConfig()
    p = prepare(case.scene, case.episodes, ALL_EFFECTS, config)
    model, _ = truth_model(case, max(1, len(p.split.folds)) if p.split.cross_validated else 1)
    return case, p, model, heldout_pairs(p, model, config)[0]
