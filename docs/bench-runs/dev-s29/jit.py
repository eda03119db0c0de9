"""Prototype: timing-jitter estimate from fourth differences against local speed."""
import sys, json, numpy as np
from voe.gap.bench import make_case
from voe.gap.shooting import noise_model

C2 = np.array([1, 16, 36, 16, 1.0])  # squared d4 coefficients


def jitter_stats(eps, sigma, nbins=8):
    rows = []  # (d4^2, u, b, c)
    for e in eps:
        if len(e.t) < 12:
            continue
        dt = np.median(np.diff(e.t))
        d4 = np.diff(e.pose, n=4, axis=0)  # (T-4, B, 3)
        # smoothed speed: central difference over +-3 samples
        k = 3
        v = np.full(e.pose.shape, np.nan)
        v[k:-k] = (e.pose[2 * k:] - e.pose[:-2 * k]) / (2 * k * dt)
        v2 = v ** 2
        u = sum(C2[i] * v2[i:len(v2) - 4 + i] for i in range(5))  # (T-4, B, 3)
        ok = np.isfinite(u)
        rows.append((d4[ok.all(axis=(1, 2))], u[ok.all(axis=(1, 2))]))
    d4 = np.concatenate([r[0] for r in rows]); u = np.concatenate([r[1] for r in rows])
    B = d4.shape[1]
    X, Y, W = [], [], []
    for b in range(B):
        for c in range(3):
            q = np.quantile(u[:, b, c], np.linspace(0, 1, nbins + 1))
            for i in range(nbins):
                m = (u[:, b, c] >= q[i]) & (u[:, b, c] <= q[i + 1])
                if m.sum() < 20:
                    continue
                V = np.median(d4[m, b, c] ** 2) / 0.4549  # robust variance
                X.append((b * 3 + c, np.median(u[m, b, c]))); Y.append(V)
    X = np.array(X); Y = np.array(Y)
    # model Y = 70 s2[bc] + j2 * u, relative LSQ; shared j2
    nbc = B * 3
    A = np.zeros((len(Y), nbc + 1))
    A[np.arange(len(Y)), X[:, 0].astype(int)] = 70.0
    A[:, -1] = X[:, 1]
    coef, *_ = np.linalg.lstsq(A / Y[:, None], np.ones_like(Y), rcond=None)
    A0 = A[:, :-1]
    c0, *_ = np.linalg.lstsq(A0 / Y[:, None], np.ones_like(Y), rcond=None)
    err1 = float(np.sum((A @ coef / Y - 1) ** 2)); err0 = float(np.sum((A0 @ c0 / Y - 1) ** 2))
    j = float(np.sqrt(max(coef[-1], 0)))
    return j, err0, err1, len(Y)


if __name__ == "__main__":
    for spec in sys.argv[1:]:
        seed, truth, nk = spec.split(':')
        case = make_case(np.random.default_rng(int(seed)), truth, noise_kind=nk)
        sigma, phi = noise_model(case.episodes)
        j, e0, e1, n = jitter_stats(case.episodes, sigma)
        print(json.dumps(dict(seed=int(seed), truth=truth, nk=nk, jitter_ms=round(j * 1e3, 3), err0=round(e0, 2), err1=round(e1, 2), n=n)), flush=True)
