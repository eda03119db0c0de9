"""Verify a fitted model on held-out episodes and say in plain English what was found.

Why: a fit is only believable on data it has not seen. Held-out windows are re-simulated with and
without the accepted effects; RMSE before and after, and the share of windows whose standardised
residual still exceeds the located threshold, say whether what is left looks like noise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from voe.gap.departure import ALPHA
from voe.gap.effects.base import Effect
from voe.gap.locate import LOCAL, by_bar, window_z
from voe.gap.shooting import Shooter, Window, position_rmse, rmse, window_score

if TYPE_CHECKING:  # an annotation only: no import of the search machinery at run time
    from voe.gap.search import TieBreak


NOISE_SHARE = 0.1  # what is left looks like noise when at most this share of windows departs
EXPRESSED_Z = 3.0  # a window expresses a law when the law moves its prediction by this many noise sigmas (RMS)


@dataclass(frozen=True)
class Verification:
    """Held-out numbers before/after. RMSE in metres; ``flagged_*`` are window fractions."""

    rmse_before: float
    rmse_after: float
    position_rmse_before: float
    position_rmse_after: float
    window_median_before: float
    window_median_after: float
    median_z_before: float
    median_z_after: float
    flagged_before: float
    flagged_after: float
    looks_like_noise: bool
    z_before: tuple[float, ...] = ()  # (W,) each window's z without the model (``voe.gap.carry_over.deepened``)
    z_after: tuple[float, ...] = ()  # (W,) and with it
    # (W,) RMS over each window of how far the model moves the prediction (pose-equivalent metres); () if not taken
    moved: tuple[float, ...] = ()

    def nominal(self) -> Verification:
        """The nominal model's figures on the same windows: every *after* figure is its *before*.

        Why: a model dropped after its test figures were taken (``voe.gap.carry_over.drop_all``)
        reports the nominal model's, which ``verify`` already simulated as the *before* figures;
        simulating the test windows again would give the same numbers.
        """
        return Verification(self.rmse_before, self.rmse_before, self.position_rmse_before, self.position_rmse_before,
                            self.window_median_before, self.window_median_before, self.median_z_before,
                            self.median_z_before, self.flagged_before, self.flagged_before,
                            bool(self.flagged_before <= NOISE_SHARE), self.z_before, self.z_before,
                            tuple(0.0 for _ in self.moved))


def rms_moved(after: list[np.ndarray], before: list[np.ndarray]) -> list[float]:
    """(W,) RMS of each window's residual change (the prediction's change: the recordings cancel),
    in the residuals' units, as the bench measures a law's expression (``EXPRESSED_Z``)."""
    return [float(np.sqrt(np.mean((a - b) ** 2))) for a, b in zip(after, before, strict=True)]


def verify(shooter: Shooter, pairs: list[tuple[Window, np.ndarray | None]], effect: Effect | None,
           sigma: np.ndarray, z_thr: float) -> Verification:
    """Re-simulate each window with and without ``effect`` (at that window's parameters)."""
    windows = [w for w, _ in pairs]
    if not windows:
        nan = float("nan")
        return Verification(nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, False)
    before = shooter.residuals(windows, None, None)
    after = _residuals_at(shooter, pairs, effect) if effect is not None else before
    zb = window_z(shooter, windows, sigma, before).max(axis=(1, 2))  # (W,)
    za = window_z(shooter, windows, sigma, after).max(axis=(1, 2))  # (W,)
    flagged_after = float(np.mean(za > z_thr))
    moved = rms_moved(after, before)  # (W,)
    return Verification(rmse(before), rmse(after), position_rmse(before), position_rmse(after),
                        window_score(before), window_score(after),
                        float(np.median(zb)), float(np.median(za)), float(np.mean(zb > z_thr)), flagged_after,
                        bool(flagged_after <= NOISE_SHARE), tuple(map(float, zb)), tuple(map(float, za)), tuple(moved))


def _residuals_at(shooter: Shooter, pairs: list[tuple[Window, np.ndarray | None]], effect: Effect) -> list[np.ndarray]:
    """Residual of each window at its own parameters; windows sharing parameters are simulated together."""
    groups: dict[bytes, list[int]] = {}
    for i, (_, p) in enumerate(pairs):
        groups.setdefault(np.asarray(p, dtype=float).tobytes(), []).append(i)
    out: list[np.ndarray] = [np.empty(0)] * len(pairs)
    for idx in groups.values():
        for i, r in zip(idx, shooter.residuals([pairs[i][0] for i in idx], effect, pairs[idx[0]][1]), strict=True):
            out[i] = r
    return out


def _where(stretches: list[dict], limit: int = 4) -> str:
    """Where and when the strongest of ``stretches`` are, in words; a stretch located against its
    windows' own clean replicates (``bar = "local"``: ``voe.gap.stages.locate_parts``) says so,
    with the largest of those replicates' z."""
    strong = sorted(stretches, key=lambda x: -x["z"] if np.isfinite(x["z"]) else -1e300)
    bits = []
    for x in strong[:limit]:
        r = x["region"]
        bar = f", bar {x['bar_z']:.1f}" if x["bar"] == LOCAL else ""
        bits.append(f"{x['body']} in episode {x['episode']} at t = {x['t_start']:.2f}-{x['t_end']:.2f} s, "
                    f"x {r[0]:.2f}..{r[1]:.2f} m ({x['context']}, z = {x['z']:.1f}{bar})")
    more = f"; and {len(strong) - limit} more" if len(strong) > limit else ""
    return "; ".join(bits) + more


def _value(v: float, lo: float, hi: float) -> str:
    return f"{v:.3g} (95 % interval {lo:.3g} to {hi:.3g})"


def _spread(departure_p: float | None) -> str:
    """The clause a ``consistent`` text owes when nothing is located but the windows as a whole depart.

    Why: ``unexplained`` needs a located stretch (``voe.gap.finder.unnamed_verdict``), so data whose
    every window departs a little, none beyond the clean replicate's largest z, read ``consistent``;
    the text must not then claim agreement that the departure test contradicts. Development case
    6219139 (a gust; seed 6219, session 41): nothing located (the clean replicate's largest window z
    116.2), departure p = 0.001, and the text said only that no stretch departs.
    """
    if departure_p is None or not departure_p < ALPHA:
        return ""
    return (f"; but across all windows the recordings depart more than the replicate does (departure p = "
            f"{departure_p:.2g}; signed-rank and tail-excess tests, Bonferroni-combined), spread over windows "
            "too evenly to be located: a lead to check, not agreement")


def explain(verdict: str, effects: list[dict], groups: list[list[str]], located: list[dict], ver: Verification,
            threshold: float, sigma: np.ndarray, test_note: str, z_strong: float, dropped: tuple[dict, ...] = (),
            best: tuple[str, float] | None = None, ties: list[TieBreak | None] | None = None,
            departure_p: float | None = None, z_floor: float = 5.0) -> str:
    """A short paragraph with the numbers that matter; it never claims agreement next to a mismatch.
    ``z_floor``: the location's floor (``GapConfig.z_min``), which a window located against its own
    replicates must pass too."""
    noise_mm = 1e3 * float(np.median(sigma[:, :2]))
    tail = "".join(f" {d['effect']} was dropped: {d['reason']}." for d in dropped)
    if verdict == "consistent":
        isolated = [x for x in located if not x["z"] <= z_strong]
        spread = "" if isolated else _spread(departure_p)
        where = (f"no stretch departs by more than clean simulated data does (largest window z there {z_strong:.1f})"
                 + spread
                 if not isolated else
                 f"{len(isolated)} stretch(es) exceed the clean replicate's largest window z ({z_strong:.1f}): "
                 f"{_where(isolated)}, but across all windows the recordings depart no more than the "
                 f"replicate does (departure p = {departure_p if departure_p is not None else float('nan'):.2g};"
                 f" signed-rank and tail-excess tests, Bonferroni-combined), as isolated chaotic windows do")
        cut = ("no candidate effect that cut the selection error by more than the null threshold of "
               f"{100 * threshold:.1f} % has a strength distinguishable from the nominal scene" if dropped else
               f"no candidate effect cut the selection error by more than the null threshold of {100 * threshold:.1f} %")
        lead = ("Nothing is located and no library effect is named, but the recordings are not shown to agree with "
                "the nominal simulation" if spread else "The recordings are consistent with the nominal simulation")
        text = f"{lead}: {where}, and {cut} (noise floor about {noise_mm:.3g} mm)."
        return text + tail
    if verdict == "unexplained":
        test = "" if departure_p is None else f", departure p = {departure_p:.2g} (signed-rank and tail-excess tests, Bonferroni-combined)"
        local = by_bar(located, LOCAL)
        if local:  # nothing passed the one bar: each window was held against its own clean replicates
            where = (f"{len(local)} stretch(es) located window by window (no stretch's median window z passed the "
                     f"clean replicate's 95th-percentile window z, {z_strong:.1f}, but each of these windows is above "
                     f"every window-local clean replicate of it and z = {z_floor:g}; a stretch's bar is the largest of "
                     f"these over its windows): {_where(local)}")
        else:
            strong = [x for x in located if not x["z"] <= z_strong]
            where = f"{len(strong)} located stretch(es) (z above {z_strong:.1f}): {_where(strong)}"
        text = (f"The recordings depart from the nominal simulation in {where}; across all windows they depart "
                f"more than clean simulated data does{test}. No effect in the library explains it")
        if best is not None and np.isfinite(best[1]):
            text += f" (the best candidate, {best[0]}, cut the selection error by {100 * best[1]:.1f} %, "
            text += f"threshold {100 * threshold:.1f} %)"
        return text + "." + tail
    parts = []
    for e in effects:
        ps = ", ".join(f"{k} = {_value(v, *e['interval95'][k])}" for k, v in e["params"].items())
        parts.append(f"{e['summary']}: {e['name']} ({ps}) was missing")
    drop = 100 * (1 - ver.rmse_after / ver.rmse_before) if ver.rmse_before > 0 else 0.0
    them = "them" if len(effects) > 1 else "it"
    errs = (f"(RMSE of x, y and angle x sqrt(I/m)) on {test_note} from {ver.rmse_before:.3g} m to "
            f"{ver.rmse_after:.3g} m")
    pos = f"position only {ver.position_rmse_before:.3g} m to {ver.position_rmse_after:.3g} m"
    if drop > 0:
        text = "; ".join(parts) + f". Adding {them} cuts the error {errs} ({drop:.0f} % less; {pos})."
    else:  # chosen and accepted on the selection episodes, not borne out on the test ones: say so
        text = "; ".join(parts) + (
            f". But adding {them} does not cut the error {errs} ({-drop:.0f} % more; {pos}): what was fitted "
            f"on the fitting and selection episodes does not carry over to the test episodes, so treat "
            f"{them} as a lead to check, not a finding.")
    if located:
        ctxs = sorted({x["context"].split()[0] for x in located})
        how = (" (window by window, against clean replicates of the same windows)"
               if by_bar(located, LOCAL) else "")
        text += f" The mismatch was located in {len(located)} stretch(es){how}, context: {', '.join(ctxs)}."
    for g, tie in zip(groups, ties or [None] * len(groups), strict=True):
        if len(g) > 1 and tie is not None:
            text += (f" {' and '.join(g)} fit the selection windows within 10 % of each other; {g[0]} fits best on "
                     f"the windows where their predictions differ" +
                     (f", but there are {tie.n_differ} of them, too few to rule out {' and '.join(g[1:])}."
                      if tie.unproven else "."))
        elif len(g) > 1:
            text += f" The data cannot tell apart {' and '.join(g)} (selection errors within 10 %); {g[0]} is named first."
    text += (" The remaining residuals look like noise." if ver.looks_like_noise else
             f" {100 * ver.flagged_after:.0f} % of test windows still exceed the noise threshold.")
    return text + tail
