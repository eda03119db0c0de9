"""A later round's member whose own part changes no selection window's prediction: a stand-in.

Why: from the second round on, every candidate is fitted jointly with the parts already accepted,
and the joint fit moves those parts too. The selection gain of a strong first effect is jagged in
its parameters at the scale of its own 95 % interval (collision windows whose outcome flips), so
a joint fit can gain the floor or more by landing the earlier parts on a luckier spot while its
own part stays at its nominal values. Measured on ``bench/gap_speed.py``'s case (a quadratic drag
alone; ``docs/bench-runs/dev-s66/si_speed.txt``): round 2's ``constant_acceleration``,
``linear_drag``, ``friction`` and ``mass[ball]`` gained 6.4-6.6 % over round 1 with their own
parts at 0.0002/-0.0036 m/s^2, 0, the nominal friction and 0.9996; set back to nominal, no
selection window's prediction moved by more than 0.43 noise sigmas. They passed on trial, and
the search ran a third round and the check took them apart (3.5 times the rollouts of the
search before the half step). Development compound 6056131 (``quadratic_drag`` + ``friction``):
round 2's ``mass[ball]`` = 0.596 gained 15.4 %, more than the true friction's 14.7 %, and moved
no window by 0.1 sigma (the ball never hits anything in a selection window); the friction moved
one window by 5.2 sigmas. True second effects measured the same way move some window by far
more than one sigma: 8587117's ``mass[ball]`` 39, 5025137's ``rolling_resistance`` 22.

So a member whose own part, set to its nominal values (NaN ones, such as a position, kept) with
the earlier parts where the joint fit put them, moves no selection window's prediction by
``STAND_IN_Z`` noise sigmas (RMS over the window, ``voe.gap.verify.rms_moved``) is not a
candidate of that round, in the data's search and the null's alike (the null's threshold is the
best gain of the same eligible members on clean data). One sigma, not the bench's
``EXPRESSED_Z`` (3): below one sigma the part's own change is inside the noise of every window,
so what the joint fit gained there is the earlier parts'; a law felt at a sigma or two in many
windows is still a candidate. It stays in the pool for later rounds.
"""

from __future__ import annotations

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.fit import FitResult
from voe.gap.folds import FoldedFitter
from voe.gap.verify import rms_moved

STAND_IN_Z = 1.0  # a later round's member must move some selection window's prediction by this many noise sigmas


def own_moved(fitter: FoldedFitter, res: FitResult, cand: Effect) -> float:
    """Largest RMS change, in noise sigmas, of a selection window's prediction between the joint
    fit ``res`` (newest part ``cand``) and the same fit with ``cand``'s parameters at their
    nominal values in every fold; the earlier parts stay where the joint fit put them.
    ``inf`` for a fit that blew up (it is judged by its gain, as before)."""
    q = cand.n_params
    if q == 0 or not np.all(np.isfinite(res.window_sse)):
        return float("inf")
    back = []
    for f, p in zip(fitter.folds, res.fold_params, strict=True):
        nom = cand.nominal(f.ctx)  # (q,)
        back.append(np.concatenate([p[:-q], np.where(np.isfinite(nom), nom, p[-q:])]))
    moved = rms_moved(fitter.residuals(res.effect, res.fold_params), fitter.residuals(res.effect, tuple(back)))  # (W,)
    noise = float(np.median(fitter.folds[0].sigma[:, :2]))
    return max(moved, default=0.0) / max(noise, 1e-300)


def is_stand_in(moved: float) -> bool:
    """Whether a later round's member with ``own_moved`` = ``moved`` is a stand-in (see the module)."""
    return moved < STAND_IN_Z
