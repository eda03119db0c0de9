from voe.scoring.verdict import INCONCLUSIVE, LEARNED, NOT_LEARNED, RULE, verdict


def test_verdict_rule_examples():
    assert verdict(0.95, 0.85, 1.0, 0.001) == (LEARNED, "")
    assert verdict(0.95, 0.85, 1.0, 0.2) == (INCONCLUSIVE, "")  # not significant after Holm
    assert verdict(0.7, 0.6, 0.8, 0.001) == (INCONCLUSIVE, "")  # above chance, below the bar
    assert verdict(0.62, 0.55, 0.69, 0.001) == (NOT_LEARNED, "")  # bar ruled out
    assert verdict(0.5, 0.5, 0.5, 1.0) == (NOT_LEARNED, "chance")  # blind model
    assert verdict(0.5, 0.2, 0.8, 0.6) == (INCONCLUSIVE, "chance")  # too few sets
    assert verdict(0.1, 0.0, 0.3, 1.0) == (NOT_LEARNED, "reversed")
    assert verdict(float("nan"), float("nan"), float("nan"), float("nan"))[0] == INCONCLUSIVE
    assert "learned" in RULE and "0.75" in RULE
