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


def test_false_discovery_is_also_printed_on_the_earlier_runs_clean_cases():
    """A run with more extra clean cases than the earlier runs' 89 prints the false-discovery
    line twice per noise kind: over every clean case, and over the cycle's and the first 89 extra
    ones (lowest case ids), which are the same cases as an earlier ``--clean 89`` run."""
    def clean(seed, named):
        return {**_case("none", ["friction"] if named else []), "seed": seed, "role": "clean"}
    cycle = {**_case("none", []), "seed": 0}
    extra = [clean(150 + i, named=i in (3, 100)) for i in range(120)]  # one FD among the first 89, one after
    lines = summary_lines([cycle] + extra[::-1], 1e-3)
    fd = [x for x in lines if x.startswith("false discovery")]
    assert fd[0].startswith("false discovery on clean (white noise): 2/121 = 2 %")
    assert fd[1].startswith("false discovery on clean (white noise, cycle and first 89 extra clean (as --clean 89)): "
                            "1/90 = 1 %")
    assert len([x for x in summary_lines([cycle] + extra[:89], 1e-3) if x.startswith("false discovery")]) == 1


def test_a_clean_case_called_unexplained_is_a_false_discovery():
    """``unexplained`` on clean data claims missing physics as a named effect does: both count,
    in the line and in the target."""
    from voe.gap.bench_score import targets

    def clean(i, names=(), verdict="consistent"):
        return {**_case("none", list(names), verdict=verdict), "seed": 150 + i, "role": "clean"}
    rs = [clean(i) for i in range(40)]
    rs[3] = clean(3, verdict="unexplained")
    rs[7] = clean(7, ["friction"])
    line = next(x for x in summary_lines(rs, 1e-3) if x.startswith("false discovery"))
    assert line.startswith("false discovery on clean (white noise): 2/40 = 5 %, of which 1 unexplained")
    assert next(ok for name, ok in targets(rs) if name.startswith("false discovery (white)")) is False  # bound > 8 %
    rs[3] = clean(3)
    assert "1/40 = 2 %, of which 0 unexplained" in next(x for x in summary_lines(rs, 1e-3) if x.startswith("false discovery"))


def test_targets_are_judged_unrounded():
    """123/130 = 94.6 % printed "95 %" in earlier runs; the target lines judge the exact counts,
    and an out-of-library case left ``consistent`` fails "the rest named correctly or unexplained"."""
    from voe.gap.bench_score import target_lines, targets

    def cycle(n_right, n):
        return [_case("mass", ["mass"] if i < n_right else []) for i in range(n)]

    def met(results, prefix):
        return next(ok for name, ok in targets(results) if name.startswith(prefix))

    assert met(cycle(123, 130), "singles") is False  # 94.6 %
    assert met(cycle(124, 130), "singles") is True  # 95.4 %, CP lower bound 90.2 %
    assert met(cycle(105, 110), "singles") is False  # 95.5 % but CP lower bound 89.7 %
    patch = {**_case("floor_patch", [], "outside", "unexplained"), "located": 3}
    quiet = {**_case("floor_patch", [], "outside", "consistent"), "located": 0}
    wrong = {**_case("gust", ["linear_drag"], "outside"), "located": 3}
    assert met([patch] * 9 + [wrong], "out-of-library misnamed") is True
    assert met([patch] * 9 + [wrong], "out-of-library, the rest") is True
    assert met([patch] * 8 + [quiet, wrong], "out-of-library, the rest") is False
    assert met([patch] * 8 + [wrong, wrong], "out-of-library misnamed") is False
    assert met(cycle(5, 5), "compounds") is None  # no compound case: not shown
    last = target_lines(cycle(123, 130))[-1]
    assert last.startswith("targets met: ") and "not met: " in last and "singles" in last
