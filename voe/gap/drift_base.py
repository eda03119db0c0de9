"""What both drift tests share: the verdict they return, the critical value and the materiality floor.

Why a module of its own: the window (Chow) test on a model's parameters (``voe.gap.drift``) and the
free-flight residual test (``voe.gap.drift_flight``) report the same ``Drift``, at the same
family-wise ``ALPHA``, held to the same ``MATERIAL`` floor; ``voe.gap.drift`` calls the flight test,
so these live below both.
"""

from __future__ import annotations

from dataclasses import dataclass

ALPHA = 0.05  # family-wise over every slot and parameter of a model (Bonferroni), as the null's alpha
#: A flight drift must be at least this fraction of the missing acceleration it is part of.
#: Session 9, on dev seeds: a constant acceleration fitted to each of the 12 zero-mean gusts of
#: seeds 5151, 6263 and 7741 leaves a slot differing by 0.89-2.39 times the median missing
#: acceleration (the gust's own swing); right effects fitted slightly off left 0.04 (7741009,
#: quadratic drag) and 0.12 (7741041, a constant acceleration of 0.57 m/s^2 dropped at 0.1).
#: 0.3 lies between the two, near their geometric middle.
MATERIAL = 0.3
#: Parameter drifts are held to the same floor, relative to the part's strength (each side's
#: distance from the nominal value; parameters without one, such as positions, have no floor).
#: Session 14, development cases of seed 7857 where a right effect was dropped as drifting: a
#: linear drag (7857006, true c = 0.217) at 0.195 in the windows centred 0.5 s against 0.219
#: elsewhere (z = 5.4, a difference of 11 % of the strength) and a joint friction (7857057, true
#: 0.029) at 0.031 against 0.026 (z = 5.0, 18 %): fits on a quarter-second slot carry start-state
#: errors that the windows' spread does not show. A constant fitted to a zero-mean gust differs
#: between slots by about its own size or more.


def critical(df: int, n_tests: int, alpha: float | None = None) -> float:
    """Two-sided Student-t critical value at ``alpha / n_tests``.

    Why t and not normal: a side's spread is estimated from a few windows (3 to 12), and with
    normal quantiles a true linear drag at its true value (development case 8019) drifted at
    z = 5.3 between a slot of 4 windows and the rest.
    """
    from scipy.stats import t as student

    alpha = ALPHA if alpha is None else alpha
    return float(student.ppf(1 - alpha / (2 * max(n_tests, 1)), max(df, 1)))


@dataclass(frozen=True)
class Drift:
    """One part's worst parameter difference between two subsamples of windows."""

    part: int
    param: str
    split: str  # "time A s": the windows (flight: units) at A s into the episodes against the rest; flight only,
    # "before A s": the units before A s against those from A s on (``voe.gap.drift_flight.flight_contrasts``)
    early: float
    late: float
    z: float

    flight: bool = False  # from the free-flight residual (``voe.gap.drift_flight``), not the parameters

    def reason(self) -> str:
        if self.flight:
            at = self.split.split(' ', 1)[1]
            where = (f"before {at} into the episodes differs from the times after" if self.split.startswith("before")
                     else f"in the slot starting {at} into the episodes differs from the other times")
            return (f"in free flight the acceleration left unexplained {where} ({self.param}: {self.early:.3g} against "
                    f"{self.late:.3g} m/s^2, t = {self.z:.1f}, family-wise p < {ALPHA:g}): what is missing changes in "
                    f"time, which no library effect does")
        what = f"the windows centred {self.split.split(' ', 1)[1]} into the episodes and on the others"
        return (f"fitted on {what} it differs ({self.param} = {self.early:.3g} against {self.late:.3g}, "
                f"{self.z:.0f} standard deviations apart, family-wise p < {ALPHA:g}): it changes in "
                f"time, which no library effect does")
