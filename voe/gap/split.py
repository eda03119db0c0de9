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

Cross-fitting (``GapConfig.cross_fit``; by default only as a second look when the three-way split
named nothing, ``GapConfig.second_look`` in ``voe.gap.finder``): a three-way split's fit/selection cut leaves a
truth felt in few windows (a box mass felt only in collisions, a rolling resistance only while
the ball rolls) with too few selection windows to pass the bootstrap (``voe.gap.bench.expression``).
With cross-fitting the episodes before the test split are halved, one fold fits on the first half
and selects on the second and the other the other way round, so every non-test episode selects
(and each fold still fits on windows it never selects on), at twice the fitting work. The test
episodes stay untouched, as in the three-way split.
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
        """Cross-validation over episodes: every episode tests in some fold, none is untouched."""
        return bool(self.folds) and not self.test

    @property
    def cross_fitted(self) -> bool:
        """Two folds swapping fitting and selection halves, with an untouched test split."""
        return bool(self.folds) and bool(self.test)

    @property
    def fit_select(self) -> tuple[tuple[tuple[int, ...], tuple[int, ...]], ...]:
        """(fitting, selecting) indices per fold; the three-way split is one fold."""
        return tuple((f, s) for f, s, _ in self.folds) or ((self.fit, self.select),)

    @property
    def scheme(self) -> str:
        """``cross-validation``, ``cross-fitting`` or ``three-way``."""
        return "cross-validation" if self.cross_validated else "cross-fitting" if self.cross_fitted else "three-way"

    def roles(self, episodes: list[Episode]) -> dict:
        """Episode ids per role, for gap.json."""
        ids = [e.id for e in episodes]
        out = {"scheme": self.scheme, "note": self.note,
               "fit": [ids[i] for i in self.fit], "select": [ids[i] for i in self.select],
               "test": [ids[i] for i in self.test]}
        if self.folds:
            out["folds"] = [{"fit": [ids[i] for i in f], "select": [ids[i] for i in s], "test": [ids[i] for i in t]}
                            for f, s, t in self.folds]
        return out


def split_episodes(n: int, cross_fit: bool = False) -> Split:
    """Chronological three-way split of ``n`` episodes (cross-fitted if ``cross_fit``: see the
    module docstring), or rotating cross-validation folds if too few."""
    n_test = max(1, round(n / 6))  # the last sixth tests in both forms of the split
    if n >= MIN_THREE_WAY and cross_fit:
        half = (n - n_test) // 2
        a, b, test = tuple(range(half)), tuple(range(half, n - n_test)), tuple(range(n - n_test, n))
        return Split(a + b, a + b, test, ((a, b, test), (b, a, test)),
                     note=f"cross-fitting: {len(a)} episodes fit while the next {len(b)} select, and the other way "
                          f"round; {n_test} test episode(s) untouched")
    if n >= MIN_THREE_WAY:
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
