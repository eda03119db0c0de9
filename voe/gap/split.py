"""Which episodes fit parameters, which select and accept effects, and which give the test figure.

Why three roles: held-out windows that pick the winner, pick refined against unrefined
parameters and decide acceptance are no longer held out when they are then reported as the
held-out improvement. So episodes are split chronologically into fitting (the first half),
selection (the next third) and test (the last sixth, at least one episode), and everything
estimated from data (the fit context, starting points, scales) comes from the fitting episodes
only. With fewer than ``MIN_THREE_WAY`` episodes there is not enough for three roles, and
reusing episodes would be dishonest: the finder then cross-validates over episodes (each
episode in turn selects, the others fit) and says so; the test figure is then the
cross-validated one, and there is no untouched test split.
"""

from __future__ import annotations

from dataclasses import dataclass

from voe.gap.recordings import Episode

MIN_THREE_WAY = 4


@dataclass(frozen=True)
class Split:
    """Episode indices (into the episode list) per role.

    Attributes:
        fit, select, test: roles for a three-way split; in cross-validation ``fit`` lists every
            episode and ``select``/``test`` are empty (the folds say who selects).
        folds: cross-validation folds as (fitting indices, selecting indices); () for three-way.
        note: one sentence for gap.json and gap.md saying which scheme was used and why.
    """

    fit: tuple[int, ...]
    select: tuple[int, ...]
    test: tuple[int, ...]
    folds: tuple[tuple[tuple[int, ...], tuple[int, ...]], ...] = ()
    note: str = ""

    @property
    def cross_validated(self) -> bool:
        return bool(self.folds)

    def roles(self, episodes: list[Episode]) -> dict:
        """Episode ids per role, for gap.json."""
        ids = [e.id for e in episodes]
        out = {"scheme": "cross-validation" if self.folds else "three-way", "note": self.note,
               "fit": [ids[i] for i in self.fit], "select": [ids[i] for i in self.select],
               "test": [ids[i] for i in self.test]}
        if self.folds:
            out["folds"] = [{"fit": [ids[i] for i in f], "select_and_test": [ids[i] for i in s]} for f, s in self.folds]
        return out


def split_episodes(n: int) -> Split:
    """Chronological three-way split of ``n`` episodes, or leave-one-episode-out folds if too few."""
    if n >= MIN_THREE_WAY:
        n_test = max(1, round(n / 6))
        n_sel = max(1, round(n / 3))
        n_fit = n - n_test - n_sel
        idx = list(range(n))
        return Split(tuple(idx[:n_fit]), tuple(idx[n_fit:n_fit + n_sel]), tuple(idx[n_fit + n_sel:]),
                     note=f"three-way split: {n_fit} fitting, {n_sel} selection, {n_test} test episode(s)")
    if n < 2:
        raise ValueError("at least two episodes are needed (split one recording into episodes)")
    folds = tuple((tuple(j for j in range(n) if j != i), (i,)) for i in range(n))
    return Split(tuple(range(n)), (), (), folds,
                 note=f"only {n} episodes (a three-way split needs {MIN_THREE_WAY}): cross-validation over "
                      f"episodes, each one in turn selecting while the others fit; no untouched test split")
