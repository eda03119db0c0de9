"""Score a gap bench run: the printed lines, each with its target.

Why separate from the cases: what counts as right differs by kind of truth (one effect, two at
once, physics outside the library, nothing), and each rule should be readable on its own.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from voe.gap.truths import OUTSIDE, single_truths

# Untouched runs up to session 23 used --clean 89; a larger run also prints the figure for those cases.
EARLIER_CLEAN = 89


def clopper_pearson(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Exact (Clopper-Pearson) two-sided confidence interval of a binomial proportion k/n."""
    from scipy.stats import beta

    if n == 0:
        return 0.0, 1.0
    a = (1 - level) / 2
    lo = 0.0 if k == 0 else float(beta.ppf(a, k, n - k + 1))
    hi = 1.0 if k == n else float(beta.ppf(1 - a, k + 1, n - k))
    return lo, hi


def outside_right(r: dict) -> bool:
    """An out-of-library truth is right if only acceptable names are given, or if nothing is
    named and the verdict says ``unexplained`` with located stretches."""
    ok = set(OUTSIDE.get(r["truth"], ()))
    if r["names"]:
        return r["names"][0] in ok
    return r["verdict"] == "unexplained" and r["located"] > 0


def misnamed(r: dict) -> bool:
    return bool(r["names"]) and r["names"][0] not in set(OUTSIDE.get(r["truth"], ()))


def beyond_truth(r: dict) -> int:
    """Named effects of case ``r`` that are not part of its truth (wrong or extra names)."""
    return sum(n not in set(r["truth"].split("+")) for n in r["names"])


def beyond_line(results: list[dict]) -> str:
    """Effects named beyond the truth, over the single-effect and compound cases (truth ``none``
    excluded: that is the false-discovery line).

    Why: the null-strength line is a guard that the check step keeps at zero by construction;
    this figure can fail. A false discovery on top of a real effect (an empty second effect
    taking the credit for refitting the first, as in the issue) shows here and nowhere else.
    """
    rs = [r for r in results if r["kind"] in ("single", "compound") and r["truth"] != "none" and r["verdict"] != "error"]
    extra = [beyond_truth(r) for r in rs]
    named = sum(len(r["names"]) for r in rs)
    return (f"effects named beyond the truth (single-effect and compound cases): {sum(extra)} of {named} named "
            f"effects are not in the truth, in {_pct(sum(e > 0 for e in extra), len(rs))} of cases")


def _pct(k: int, n: int) -> str:
    return f"{k}/{n} = {100 * k / max(1, n):.0f} %"


def summary_lines(results: list[dict], noise: float) -> list[str]:
    """Confusion matrix and every quality figure of the bench."""
    names = list(single_truths())
    cycle = [r for r in results if r.get("role") == "cycle"]
    found_names = sorted({r["found"] for r in cycle} | set(names), key=lambda n: (n not in names, names.index(n) if n in names else 0))
    short = {n: n[:6] for n in found_names}
    lines = [f"gap bench: {len(results)} cases ({len(cycle)} single-truth cycle, "
             f"{sum(r.get('role') == 'compound' for r in results)} compound, "
             f"{sum(r.get('role') == 'outside' for r in results)} out-of-library, "
             f"{sum(r.get('role') == 'clean' for r in results)} extra clean), noise {noise * 1e3:g} mm, 100 Hz",
             "confusion (rows true, cols first named): " + " ".join(f"{short[n]:>6}" for n in found_names)]
    for t in names:
        row = [sum(1 for r in cycle if r["truth"] == t and r["found"] == f) for f in found_names]
        if sum(row):
            lines.append(f"  {t:>26} " + " ".join(f"{c:>6d}" for c in row))
    correct = sum(r["truth"] == r["found"] for r in cycle)
    lo, hi = clopper_pearson(correct, len(cycle))
    lines.append(f"single-effect identification (cycle, none included): {correct}/{len(cycle)} = "
                 f"{100 * correct / max(1, len(cycle)):.1f} % (95 % CI {100 * lo:.1f}-{100 * hi:.1f} %; "
                 "target >= 95 %, CI lower bound >= 90 %)")
    lines += expression_lines(cycle)
    comp = [r for r in results if r["kind"] == "compound"]
    if comp:
        both = sum(set(r["truth"].split("+")) <= set(r["names"]) for r in comp)
        lines.append(f"compound truths, both effects named: {_pct(both, len(comp))} (target >= 80 %)")
    outs = [r for r in results if r["kind"] == "outside"]
    if outs:
        lines.append(f"out-of-library truths: misnamed as a library effect {_pct(sum(map(misnamed, outs)), len(outs))} "
                     f"(target <= 10 %); named correctly or unexplained and located {_pct(sum(map(outside_right, outs)), len(outs))}")
        lines += outside_expression_lines(outs)
    clean = [r for r in results if r["truth"] == "none"]
    lines += false_discovery_lines(clean)
    extra = sorted((r for r in clean if r.get("role") == "clean"), key=lambda r: r["seed"])
    if len(extra) > EARLIER_CLEAN:  # the same cases as an earlier run's --clean 89, for comparison
        first = {r["seed"] for r in extra[:EARLIER_CLEAN]}
        lines += false_discovery_lines([r for r in clean if r.get("role") != "clean" or r["seed"] in first],
                                       f", cycle and first {EARLIER_CLEAN} extra clean (as --clean {EARLIER_CLEAN})")
    lines.append(f"accepted effects of null strength (interval contains the nominal value), whole bench: "
                 f"{sum(r.get('null_strength', 0) for r in results)} (target 0; a guard: the check step drops "
                 "such effects, so only a bug makes this non-zero)")
    lines.append(beyond_line(results))
    ident = [r for r in results if r["kind"] == "single" and r["truth"] != "none" and r["found"] == r["truth"]]
    perr = [r["param_error"] for r in ident if np.isfinite(r["param_error"])]
    cov = [r["covered"] for r in ident if r["covered"] is not None]
    cut = [1 - r["after"] / r["before"] for r in ident if r["before"] > 0]
    lines += [f"parameter recovery error (median relative): {100 * np.median(perr) if perr else float('nan'):.1f} %",
              f"95 % intervals containing the true parameters: {_pct(sum(cov), len(cov))} of identified cases (target >= 90 %)",
              f"median test-split RMSE reduction when identified: {100 * np.median(cut) if cut else float('nan'):.0f} % "
              f"(target >= 80 %)"]
    errors = [r for r in results if r["verdict"] == "error"]
    if errors:
        lines.append(f"errors: {len(errors)} ({errors[0]['found']})")
    return lines + target_lines(results)


def targets(results: list[dict]) -> list[tuple[str, bool | None]]:
    """Each quality target of issue 12 and whether the run meets it (None: the run has no case
    that can show it). Computed from the same results as the figures above, unrounded.

    Why: the figures are printed rounded ("123/130 = 95 %" was 94.6 %) and the targets are
    spread over many lines; a reader, and the closing note, should not have to redo the
    arithmetic to know which lines a run met. The out-of-library target is read as the issue
    writes it: at most 10 % misnamed, *and* every case not misnamed named correctly or
    ``unexplained`` and located (a ``consistent`` verdict on a floor patch is a miss).
    """
    out: list[tuple[str, bool | None]] = [(f"at least 110 cases ({len(results)})", len(results) >= 110)]
    cycle = [r for r in results if r.get("role") == "cycle"]
    k, n = sum(r["truth"] == r["found"] for r in cycle), len(cycle)
    out.append((f"singles >= 95 % and CI lower bound >= 90 % ({k}/{n})",
                (k >= 0.95 * n and clopper_pearson(k, n)[0] >= 0.90) if n else None))
    comp = [r for r in results if r["kind"] == "compound"]
    both = sum(set(r["truth"].split("+")) <= set(r["names"]) for r in comp)
    out.append((f"compounds, both named >= 80 % ({both}/{len(comp)})", both >= 0.8 * len(comp) if comp else None))
    outs = [r for r in results if r["kind"] == "outside"]
    bad, good = sum(map(misnamed, outs)), sum(map(outside_right, outs))
    out.append((f"out-of-library misnamed <= 10 % ({bad}/{len(outs)})", bad <= 0.1 * len(outs) if outs else None))
    out.append((f"out-of-library, the rest named correctly or unexplained and located ({good}/{len(outs) - bad})",
                good == len(outs) - bad if outs else None))
    clean = [r for r in results if r["truth"] == "none"]
    for nk in ("white", "coloured"):
        sub = [r for r in clean if r["noise_kind"] == nk]
        fd = sum(map(false_discovery, sub))
        out.append((f"false discovery ({nk}) <= 5 %, bound <= 8 % ({fd}/{len(sub)})",
                    (fd <= 0.05 * len(sub) and clopper_pearson(fd, len(sub))[1] <= 0.08) if sub else None))
    out.append(("no accepted effect of null strength", sum(r.get("null_strength", 0) for r in results) == 0))
    ident = [r for r in results if r["kind"] == "single" and r["truth"] != "none" and r["found"] == r["truth"]]
    cut = [1 - r["after"] / r["before"] for r in ident if r["before"] > 0]
    out.append(("median test-split RMSE reduction >= 80 %", bool(np.median(cut) >= 0.8) if cut else None))
    cov = [r["covered"] for r in ident if r["covered"] is not None]
    out.append((f"interval coverage >= 90 % ({sum(cov)}/{len(cov)})", sum(cov) >= 0.9 * len(cov) if cov else None))
    return out


def target_lines(results: list[dict]) -> list[str]:
    """``targets`` as lines, and one line naming the targets not met."""
    ts = targets(results)
    word = {True: "met", False: "NOT MET", None: "not shown by this run"}
    lines = [f"target: {word[ok]:<21} {name}" for name, ok in ts]
    missed = [name for name, ok in ts if ok is False]
    lines.append(f"targets met: {sum(ok is True for _, ok in ts)} of {len(ts)}"
                 + (f"; not met: {'; '.join(missed)}" if missed else ""))
    return lines


def false_discovery(r: dict) -> bool:
    """A clean case claims missing physics: an effect named, or the verdict ``unexplained``.

    Why both: ``unexplained`` says the recordings depart from the nominal model in a way no
    effect explains, which on clean data is as false as a named effect. Until session 28 only
    named effects were counted; the untouched runs of sessions 22-25 had no clean case called
    ``unexplained``, so their figures are the same either way."""
    return r["n_effects"] > 0 or r["verdict"] == "unexplained"


def false_discovery_lines(clean: list[dict], label: str = "") -> list[str]:
    """One line per noise kind: clean cases with a false discovery (``false_discovery``), of
    which ``unexplained``, and the 95 % Clopper-Pearson upper bound of the rate."""
    lines = []
    for nk in sorted({r["noise_kind"] for r in clean}):
        sub = [r for r in clean if r["noise_kind"] == nk]
        k = sum(map(false_discovery, sub))
        u = sum(r["verdict"] == "unexplained" for r in sub)  # names nothing: a named effect makes it "mismatch"
        lines.append(f"false discovery on clean ({nk} noise{label}): {_pct(k, len(sub))}, of which {u} unexplained "
                     f"(95 % Clopper-Pearson upper bound {100 * clopper_pearson(k, len(sub))[1]:.1f} %; target <= 5 %, "
                     f"bound <= 8 %)")
    return lines


def expression_lines(cycle: list[dict]) -> list[str]:
    """Identification of the single truths split by how many selection windows express them
    (``voe.gap.bench.expression``): a diagnostic beside the headline figure, not a replacement."""
    rows = [r for r in cycle if r["truth"] != "none" and r.get("expressed")]
    return _by_expression(rows, lambda r: r["found"] == r["truth"], "truth", "selection")


def outside_expression_lines(outs: list[dict]) -> list[str]:
    """The out-of-library truths right (``outside_right``) split by how many of the location's 1-s
    windows the floor patch moves (``voe.gap.bench.expression``; gusts are not simulated window by
    window): whether the misses are patches the recordings show, or patches that leave no trace a
    finder could honestly report. A diagnostic beside the target, not a replacement."""
    return _by_expression([r for r in outs if r.get("expressed")], outside_right, "floor patch", "location")


def _by_expression(rows: list[dict], right: Callable[[dict], bool], what: str, windows: str) -> list[str]:
    if not rows:
        return []
    strong = [r for r in rows if r["expressed"][0] >= 3]
    weak = [r for r in rows if r["expressed"][0] < 3]
    ok = lambda rs: sum(map(right, rs))  # noqa: E731
    return [f"  by expression ({what} moves a {windows} window's prediction by > 3 noise sigmas): in 3 or more "
            f"windows {_pct(ok(strong), len(strong))}; in fewer {_pct(ok(weak), len(weak))}"]
