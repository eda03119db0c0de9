"""Windows a floor patch cannot touch: rolled out once without the patch, reused for every patch.

Why: a region material (``friction_region``, ``restitution_region``) is set per contact by a
Python pre-solve callback, which more than doubles a rollout's cost, and its fit tries many
patches: 74 starting intervals ranked on every fitting window, then Powell moving the edges.
Many windows touch the floor only far from a given patch, or not at all, and there a patch changes
nothing to the bit (``voe.sim.scenefile.region_inert``): on ``bench/gap_speed.py``'s case, 36 % of the
region windows asked for are such windows (``docs/bench-runs/dev-s51``). So the windows are simulated once with
the model's other parts and no patch, recording where they touch the floor; a window whose
contacts a patch leaves exactly as they were is given those poses, the rest are simulated with
the patch. The answers are the same to the bit (``tests/gap/test_bare.py``); only the cost falls.

The patchless rollout is one extra rollout per window, so it is made only for a model met
before with another patch (its key, the parameters with the patch's blanked, seen twice): a
start screen or a fit that moves only the patch, not a fit that moves everything at once.
"""

from __future__ import annotations

from collections import OrderedDict
from typing import TYPE_CHECKING

import numpy as np

from voe.gap.effects.base import Effect
from voe.gap.rollout import run_many_recorded
from voe.sim.scenefile import region_inert

if TYPE_CHECKING:
    from voe.gap.shooting import Shooter, Window

SEEN = 4096  # patchless models remembered as seen
MEMO = 512  # patchless windows remembered (poses and contacts: up to ~25 kB each)


def bare_params(effect: Effect | None, params: np.ndarray | None, scene) -> np.ndarray | None:
    """``params`` with every region-material part's parameters set to NaN (what the patchless
    rollout does not depend on), or None if ``effect`` has no such part or one also has forces."""
    if effect is None or params is None:
        return None
    p = np.array(params, dtype=float)
    i, found = 0, False
    for part in effect.parts:
        n = part.n_params
        m = part.materials(p[i:i + n], scene)
        if m.region_friction is not None or m.region_elasticity is not None:
            if part.has_forces:
                return None
            p[i:i + n], found = np.nan, True
        i += n
    return p if found else None


class Bare:
    """The patchless rollouts of one ``Shooter``: its memo and the models seen."""

    def __init__(self) -> None:
        self.seen: OrderedDict[tuple, None] = OrderedDict()
        self.memo: OrderedDict[tuple, tuple[np.ndarray, np.ndarray]] = OrderedDict()
        self.n_reused = 0  # windows given patchless poses (for the speed bench's accounting)

    def simulate(self, shooter: Shooter, wins: list[Window], effect: Effect | None, params: np.ndarray | None,
                 key: tuple | None) -> list[np.ndarray]:
        """Poses (n_i, B, 3) of ``wins`` under ``effect`` at ``params``, as ``run_many`` gives them.

        Args:
            key: the Shooter's memo key of ``effect`` and ``params`` (None: not a library effect).
        """
        bp = bare_params(effect, params, shooter.scene) if key is not None else None
        bkey = None if bp is None else key[:2] + (bp.tobytes(),)  # type: ignore[index]
        if bkey is None or not self._seen(bkey):
            return shooter.run(wins, effect, params)
        keys = [(bkey, w.ep, w.k0, w.k1) for w in wins]
        got = {k: self.memo[k] for k in keys if k in self.memo}  # read before the memo is trimmed below
        for k in got:
            self.memo.move_to_end(k)
        missing = [i for i, k in enumerate(keys) if k not in got]
        if missing:
            sub = [wins[i] for i in missing]
            poses, contacts, _ = run_many_recorded(shooter.scene, *shooter.starts_times(sub), shooter.substep,
                                                   effect, params)
            for i, pose, c in zip(missing, poses, contacts, strict=True):
                self.memo[keys[i]] = got[keys[i]] = (pose, c)
            while len(self.memo) > MEMO:  # may drop this call's own windows: they are read from ``got``
                self.memo.popitem(last=False)
        mats = effect.materials(params, shooter.scene)
        out: list[np.ndarray | None] = [None] * len(wins)
        todo = []
        for i, k in enumerate(keys):
            pose, c = got[k]
            if region_inert(c, mats):
                out[i] = pose.copy()
                self.n_reused += 1
            else:
                todo.append(i)
        if todo:
            for i, pose in zip(todo, shooter.run([wins[i] for i in todo], effect, params), strict=True):
                out[i] = pose
        return out  # type: ignore[return-value]

    def _seen(self, bkey: tuple) -> bool:
        """Whether the patchless model ``bkey`` was asked for before (and remember it now)."""
        if bkey in self.seen:
            self.seen.move_to_end(bkey)
            return True
        self.seen[bkey] = None
        while len(self.seen) > SEEN:
            self.seen.popitem(last=False)
        return False

