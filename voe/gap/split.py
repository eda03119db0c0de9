"""Which episodes fit parameters, which select and accept effects, and which give the test figure.

Why three roles: held-out windows that pick the winner, pick refined against unrefined
parameters and decide acceptance are no longer held out when they are then reported as the
held-out improvement. So episodes are split chronologically into fitting (the first half),
selection (the next third) and test (the last sixth, at least one episode), and everything
estimated from data (the fit context, starting points, scales) comes from the fitting episodes
only. With fewer than ``MIN_THREE_WAY`` episodes there is not enough for three roles, and
reusing episodes would be dishonest: the finder then cross-validates over episodes with the
three roles rotating (in fold i episode i tests, episode i + 1 selects, the others fit), so no
episode both selects and tests in the same fold, and says so. The search chooses and accepts
one model on all folds' selection windows together, so every episode still helps choose the
effect (as another fold's selection episode); what a fold reports comes from an episode that
neither fitted nor selected in that fold, and there is no untouched test split. Fewer than three
episodes cannot fill the three roles and are refused.
"""

from __future__ import annotations

from dataclasses import dataclass

from voe.gap.recordings import Episode

MIN_THREE_WAY = 4
MIN_EPISODES = 3  # one per role: fitting, selection, test


@dataclass(frozen=True)
class Split:
    """Episode indices (into the episode list) per role.

    Attributes:
        fit, select, test: roles for a three-way split; in cross-validation ``fit`` lists every
            episode (each fits in some fold) and ``select``/``test`` are empty (the folds say).
        folds: cross-validation folds as (fitting, selecting, testing) indices; () for three-way.
        note: one sentence for gap.json and gap.md saying which scheme was used and why.
    """

    fit: tuple[int, ...]
    select: tuple[int, ...]
    test: tuple[int, ...]
    folds: tuple[tuple[tuple[int, ...], tuple[int, ...], tuple[int, ...]], ...] = ()
    note: str = ""

    @property
    def cross_validated(self) -> bool:
        return bool(self.folds)

    @property
    def fit_select(self) -> tuple[tuple[tuple[int, ...], tuple[int, ...]], ...]:
        """(fitting, selecting) indices per fold; the three-way split is one fold."""
        return tuple((f, s) for f, s, _ in self.folds) or ((self.fit, self.select),)

    def roles(self, episodes: list[Episode]) -> dict:
        """Episode ids per role, for gap.json."""
        ids = [e.id for e in episodes]
        out = {"scheme": "cross-validation" if self.folds else "three-way", "note": self.note,
               "fit": [ids[i] for i in self.fit], "select": [ids[i] for i in self.select],
               "test": [ids[i] for i in self.test]}
        if self.folds:
            out["folds"] = [{"fit": [ids[i] for i in f], "select": [ids[i] for i in s], "test": [ids[i] for i in t]}
                            for f, s, t in self.folds]
        return out


def split_episodes(n: int) -> Split:
    """Chronological three-way split of ``n`` episodes, or rotating cross-validation folds if too few."""
    if n >= MIN_THREE_WAY:
        n_test = max(1, round(n / 6))
        n_sel = max(1, round(n / 3))
        n_fit = n - n_test - n_sel
        idx = list(range(n))
        return Split(tuple(idx[:n_fit]), tuple(idx[n_fit:n_fit + n_sel]), tuple(idx[n_fit + n_sel:]),
                     note=f"three-way split: {n_fit} fitting, {n_sel} selection, {n_test} test episode(s)")
    if n < MIN_EPISODES:
        raise ValueError(f"at least {MIN_EPISODES} episodes are needed, one each to fit, select and test "
                         f"(got {n}; split the recording into episodes)")
    folds = tuple((tuple(j for j in range(n) if j not in (i, (i + 1) % n)), ((i + 1) % n,), (i,)) for i in range(n))
    return Split(tuple(range(n)), (), (), folds,
                 note=f"only {n} episodes (a three-way split needs {MIN_THREE_WAY}): cross-validation over "
                      f"episodes with the roles rotating, in each fold one episode testing, the next selecting and "
                      f"the rest fitting, so none selects and tests in the same fold; the effect is chosen on all "
                      f"folds' selection episodes together, and there is no untouched test split")
