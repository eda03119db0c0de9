"""A verdict per model and concept: learned, not learned or inconclusive, by one stated rule.

Why a fixed, printed rule: a reader should be able to check every verdict in a report from the
numbers next to it, and nobody should be able to tune the rule after seeing the results.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

ALPHA = 0.05
#: Matched-set accuracy a model must reach to count as having learned a concept.
LEARNED_ACCURACY = 0.75

LEARNED, NOT_LEARNED, INCONCLUSIVE = "learned", "not learned", "inconclusive"
#: The verdict where the probe cannot tell: a control that knows nothing (or too little) of the
#: concept separates its clips too (``voe.controls.confound``), or the concept declares no
#: balanced design. It replaces whatever the rule above would say.
CONFOUNDED = "confounded"

RULE = (
    f"**learned** if the Holm-adjusted permutation p-value is below {ALPHA}, the lower end of the "
    f"95% bootstrap CI is above 0.5 and the matched-set accuracy is at least {LEARNED_ACCURACY}; "
    f"**not learned** if the upper end of the CI is below {LEARNED_ACCURACY} (the data rule out "
    f"the accuracy needed; this includes chance-level models, whose CI contains 0.5, and "
    f"*reversed* models, whose CI lies entirely below 0.5: they find possible events more "
    f"surprising); **inconclusive** otherwise (too few or too variable sets to decide either way)."
)


HALVES_RULE = (
    "On spliced quadruplets a concept is **learned** only if the same rule also holds for the "
    "*halves accuracy*: each impossible clip is compared with the possible clip that shows the "
    "same frame at each step (1 if more surprising, 0.5 on a tie, 0 if less; a set scores the "
    "mean of its two halves), because a memory that only grows or fades with the time an object "
    "was hidden gets one half right and the other wrong, and the sum's sign then says nothing "
    "about the law (``voe.scoring.halves``). Otherwise the halves' own verdict is given, noted "
    "*one-sided*."
)


def with_halves(sum_verdict: tuple[str, str], halves_verdict: tuple[str, str] | None) -> tuple[str, str]:
    """Combine the sum's verdict with the halves' (``None``: the concept has no quadruplets).

    Only a *learned* verdict can change: it stands if the halves are learned too, and is
    otherwise replaced by the halves' verdict (never learned), noted ``one-sided``.
    """
    if halves_verdict is None or sum_verdict[0] != LEARNED or halves_verdict[0] == LEARNED:
        return sum_verdict
    return halves_verdict[0], halves_verdict[1] if halves_verdict[1].startswith("halves") else "one-sided"


def verdict(accuracy: float, ci_low: float, ci_high: float, p_holm: float) -> tuple[str, str]:
    """Apply ``RULE``; returns ``(verdict, note)`` where note is ``'reversed'``, ``'chance'`` or ``''``."""
    if any(math.isnan(x) for x in (accuracy, ci_low, ci_high)):
        return INCONCLUSIVE, "no sets"
    note = "reversed" if ci_high < 0.5 else ("chance" if ci_low <= 0.5 <= ci_high else "")
    if not math.isnan(p_holm) and p_holm < ALPHA and ci_low > 0.5 and accuracy >= LEARNED_ACCURACY:
        return LEARNED, note
    if ci_high < LEARNED_ACCURACY:
        return NOT_LEARNED, note
    return INCONCLUSIVE, note


CONFOUNDED_RULE = (
    "**confounded** replaces the verdict on a concept when, on the same probe set and on the sets "
    "that carry the verdict (the concept's pooled sets or any one of its verdict-carrying "
    "conditions), a knowledge-free control (a statistic of the stored bytes, the stress-test "
    "classifier, or a random network of the model's own architecture, which reads the same input "
    "code) is off chance in either direction (its 95% CI excludes 0.5 and "
    f"the two-sided sign-flip p-value is below {ALPHA}; on sets that are all spliced quadruplets, "
    "read on the halves accuracy, which carries the verdict there), or a "
    "physics-poor reference is *learned* where its declared knowledge does not reach; and always "
    "when the concept declares no balanced design. The probe then cannot tell the concept from "
    "the confound, whatever a model scores."
)


def min_sets_decisive(m: int, alpha: float = ALPHA) -> int:
    """Fewest matched sets per cell for which a perfect score is *learned* after Holm over ``m``.

    A perfect score on ``n`` sets has the exact permutation p-value ``2**-n``; with ``m`` cells
    tested all perfect, Holm multiplies it by ``m``, so ``n`` must satisfy ``m * 2**-n < alpha``.
    """
    return max(1, math.floor(math.log2(max(m, 1) / alpha)) + 1)


def set_conditions(sets: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """Per matched set: its condition name and whether it carries the concept's verdict.

    The condition is the probe set's ``condition`` column when it has one, else ``visible`` /
    ``occluded`` from ``visible_violation``. Sets whose ``carries_verdict`` is False (a
    *perceptual* condition: a violation in plain view that a change detector solves) are reported
    but carry no verdict.
    """
    if "condition" in sets.columns:
        cond = sets["condition"].astype(str).to_numpy()
    else:
        cond = np.where(sets["visible_violation"].astype(bool), "visible", "occluded")
    carries = np.ones(len(sets), dtype=bool)
    if "carries_verdict" in sets.columns:
        carries = sets["carries_verdict"].fillna(True).astype(bool).to_numpy()
    return cond, carries
