"""A friction coefficient is fitted on the windows where a body slides, not on a random few."""

from __future__ import annotations

import numpy as np

from voe.gap.bench import make_case
from voe.gap.effects import EFFECTS
from voe.gap.finder import GapFinder
from voe.gap.search import window_gain
from voe.gap.stages import GapConfig, _folded, prepare


def test_friction_fit_on_its_sliding_windows_finds_a_high_coefficient():
    """Development case 9028042 (true mu 1.17, nominal 0.69), split and subsampled as the finder
    does: two of its eight random fitting windows slide, one of them mispredicted at the truth,
    and fitted there the coefficient went to 0.57 and lost 37 % on the selection windows."""
    seed = 9028042
    case = make_case(np.random.default_rng(seed), "friction", 1e-3, 12, 3.0, noise_kind="white")
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(max_effects=1, seed=seed, config=cfg).effects, cfg)
    data = _folded(p, p.shooter, p.episodes, p.bad, cfg, seed)
    eff = EFFECTS.get("friction")()
    assert eff.sparse
    f = data.folds[0]
    lo, hi = eff.bounds(f.ctx)
    on = f.focused(eff, eff.starts(f.ctx)[0], lo, hi, eff.scale(f.ctx))
    assert on is not f and 0 < len(on.train) <= len(f.train)
    assert len(set(on.train) - set(f.train)) >= 3  # mostly other windows than the random subsample
    res = data.fit_candidate(None, eff)
    assert abs(res.params[0] / case.params[0] - 1) < 0.1
    assert window_gain(data.heldout_sse(), res.window_sse) > 0.4  # the truth gains 61 % there


def test_a_hinge_part_the_fitting_windows_rule_nominal_out_for_is_established():
    """Development case 9028029 (true mu 1.26, nominal 0.59) at the focused fit 1.3993: the local
    interval holds the nominal value, the fitting windows rule it out, and the six selection
    windows do not even at the truth; asked on both sets, the part was dropped."""
    from voe.gap.check import model_intervals
    from voe.gap.effects.base import EffectSum
    from voe.gap.fit import FitResult
    from voe.gap.stages import fit_context

    seed = 9028029
    case = make_case(np.random.default_rng(seed), "friction", 1e-3, 12, 3.0, noise_kind="white")
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(max_effects=1, seed=seed, config=cfg).effects, cfg)
    ctx = fit_context(p, p.split.fit)
    eff = EffectSum((EFFECTS.get("friction")(),))
    lo, hi = model_intervals(p, p.split.fit, FitResult(eff, np.array([1.3993274364678283]), 0.0, 0.0), ctx, cfg, seed)
    nominal = float(eff.nominal(ctx)[0])
    assert lo[0] > nominal and lo[0] <= 1.3993274364678283 <= hi[0]


def test_a_sparse_part_on_a_dense_one_lets_the_dense_one_settle():
    """Development case 8367135 (``quadratic_drag`` 0.193 and ``friction`` 1.43): ``friction`` on
    top of round 0's drag, the drag held, fitted 1.35 and gained 39.8 % on the selection windows,
    below ``friction_region`` (48.0 % at the fit that won, the drag refitted to 0.198), so the
    patch was named. With the drag settled on the training windows after the friction's fit, the
    whole-floor friction predicts those windows better than the patch.

    Since session 61 (restarts from the half-step start velocity) the two tie on these windows
    (friction 53.2 %, the patch's own fit 53.7 %; before, 55.0 % against 48.0 %), within the group
    tolerance, and the finder names ``quadratic_drag`` and ``friction``
    (docs/bench-runs/dev-s61/trace_half_8367135.txt). With the drag held the friction was 8 points
    short."""
    seed = 8367135
    case = make_case(np.random.default_rng(seed), "quadratic_drag+friction", 1e-3, 12, 3.0, noise_kind="white")
    cfg = GapConfig()
    p = prepare(case.scene, case.episodes, GapFinder(max_effects=2, seed=seed, config=cfg).effects, cfg)
    data = _folded(p, p.shooter, p.episodes, p.bad, cfg, seed)
    drag = data.fit_candidate(None, EFFECTS.get("quadratic_drag")())
    res = data.fit_candidate(drag, EFFECTS.get("friction")())
    assert abs(res.params[0] - 0.193) < abs(drag.params[0] - 0.193)  # the drag moved towards its truth
    patch = data.fit_candidate(drag, EFFECTS.get("friction_region")())
    assert window_gain(drag.window_sse, res.window_sse) > window_gain(drag.window_sse, patch.window_sse) - 0.01
