"""Optimizer variants for valleys.py (monkeypatches of voe.gap.fit; dev only).
brent: Brent gets nfev iterations (not nfev minus the grid); dense: grid +-2 scales too;
expand: step past the grid's end while the cost falls (before Brent);
expand2: Brent first; only if its minimum sits at the grid's outermost point, step on outward, then Brent again."""
import numpy as np
from scipy.optimize import minimize_scalar
import voe.gap.fit as fit
from voe.gap.effects.base import Effect


def _brent(self, effect, a, b, it, scale):
    return minimize_scalar(lambda v: self.cost(effect, np.array([v])), bounds=(a, b), method="bounded",
                           options={"maxiter": it, "xatol": 0.01 * scale[0]})


def _scalar(self, effect, x0, lo, hi, scale, nfev, *, brent_all=False, expand=False, expand2=False):
    grid = fit.scalar_grid(effect, x0, lo, hi, scale)
    n_grid = len(grid)
    costs = [self.cost(effect, np.array([g])) for g in grid]
    grid = list(grid)
    if expand:  # the cost still falls at the grid's outermost point inside the bounds: step on outward
        for side in (0, -1):
            for _ in range(8):
                i = int(np.argmin(costs))
                if len(grid) < 2 or i != (0 if side == 0 else len(grid) - 1):
                    break
                end, prev = grid[i], grid[1] if side == 0 else grid[-2]
                if not (lo[0] < end < hi[0]):
                    break
                nxt = float(np.clip(end + 3 * (end - prev), lo[0], hi[0]))
                c = self.cost(effect, np.array([nxt]))
                if side == 0:
                    grid.insert(0, nxt); costs.insert(0, c)
                else:
                    grid.append(nxt); costs.append(c)
    it = max(3, nfev) if brent_all else max(3, nfev - n_grid)
    i = int(np.argmin(costs))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    x, fx = grid[i], costs[i]
    if b - a > 0:
        res = _brent(self, effect, a, b, it, scale)
        if res.fun < fx:
            x, fx = float(res.x), float(res.fun)
    if expand2:
        tol = 0.02 * scale[0]
        for side in (-1, 0):
            j = len(grid) - 1 if side == -1 else 0
            if i != j or len(grid) < 2 or not (lo[0] < grid[j] < hi[0]) or abs(x - grid[j]) > tol:
                continue
            prev, end, fend = grid[j - 1] if side == -1 else grid[1], grid[j], fx
            for _ in range(8):  # the minimum sits at the grid's end: the cost falls on beyond it
                nxt = float(np.clip(end + 3 * (end - prev), lo[0], hi[0]))
                c = self.cost(effect, np.array([nxt]))
                if c >= fend:
                    break
                prev, end, fend = end, nxt, c
                if not (lo[0] < nxt < hi[0]):
                    break
            if fend < fx:
                x, fx = end, fend
            a, b = sorted((prev, float(np.clip(end + 3 * (end - prev), lo[0], hi[0]))))
            if b - a > 0:
                res = _brent(self, effect, a, b, it, scale)
                if res.fun < fx:
                    x, fx = float(res.x), float(res.fun)
    end = (not (abs(x - grid[i]) > 0)) and i in (0, len(grid) - 1) and lo[0] < grid[i] < hi[0] and x == grid[i]
    return np.array([x]), float(fx), bool(end)


def apply(name):
    if name == "main":
        return
    parts = set(name.split("+"))
    unknown = parts - {"brent", "expand", "dense", "expand2"}
    if unknown:
        raise SystemExit(f"unknown variant part {unknown}")
    if "dense" in parts:
        def grid(self, x0, scale):
            return x0 + scale * np.array([-10.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 10.0])
        Effect.grid = grid
    fit.Fitter._scalar = lambda self, *a: _scalar(self, *a, brent_all="brent" in parts, expand="expand" in parts,
                                                  expand2="expand2" in parts)
