"""A verdict per model and concept: learned, not learned or inconclusive, by one stated rule.

Why a fixed, printed rule: a reader should be able to check every verdict in a report from the
numbers next to it, and nobody should be able to tune the rule after seeing the results.
"""

from __future__ import annotations

import math

ALPHA = 0.05
#: Matched-set accuracy a model must reach to count as having learned a concept.
LEARNED_ACCURACY = 0.75

LEARNED, NOT_LEARNED, INCONCLUSIVE = "learned", "not learned", "inconclusive"

RULE = (
    f"**learned** if the Holm-adjusted permutation p-value is below {ALPHA}, the lower end of the "
    f"95% bootstrap CI is above 0.5 and the matched-set accuracy is at least {LEARNED_ACCURACY}; "
    f"**not learned** if the upper end of the CI is below {LEARNED_ACCURACY} (the data rule out "
    f"the accuracy needed; this includes chance-level models, whose CI contains 0.5, and "
    f"*reversed* models, whose CI lies entirely below 0.5: they find possible events more "
    f"surprising); **inconclusive** otherwise (too few or too variable sets to decide either way)."
)


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
