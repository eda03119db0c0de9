"""The bench's "effects named beyond the truth" figure: it counts wrong and extra names on
single-effect and compound cases, so unlike the null-strength guard it can fail."""

from __future__ import annotations

from voe.gap.bench_score import beyond_line, summary_lines


def _case(truth, names, kind="single", verdict="mismatch"):
    return {"truth": truth, "names": names, "kind": kind, "verdict": verdict, "role": "cycle", "found": (names or ["none"])[0],
            "noise_kind": "white", "n_effects": len(names), "null_strength": 0, "param_error": float("nan"),
            "covered": None, "before": 1.0, "after": 0.5}


def test_effects_named_beyond_the_truth_counts_extra_and_wrong_names():
    results = [_case("linear_drag", ["linear_drag"]),
               _case("rolling_resistance", ["rolling_resistance", "quadratic_drag"]),  # an extra effect
               _case("friction", ["friction_region"]),  # a wrong name
               _case("restitution+linear_drag", ["linear_drag", "restitution"], "compound"),
               _case("friction+mass", ["friction", "mass", "point_attractor"], "compound"),
               _case("none", ["linear_drag"]),  # a false discovery: counted on its own line, not here
               _case("gust", ["linear_drag"], "outside"),  # misnamed out-of-library: its own line
               _case("mass", ["error"], verdict="error")]
    assert beyond_line(results) == ("effects named beyond the truth (single-effect and compound cases): 3 of 9 "
                                    "named effects are not in the truth, in 3/5 = 60 % of cases")
    assert beyond_line(results[:1] + results[3:4]).endswith(": 0 of 3 named effects are not in the truth, in 0/2 = 0 % of cases")
    lines = summary_lines(results[:2], 1e-3)
    assert any(x.startswith("effects named beyond the truth") and ": 1 of 3 " in x for x in lines)
    assert any("null strength" in x and "a guard" in x for x in lines)
