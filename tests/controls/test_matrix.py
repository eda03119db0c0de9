"""The matrix's could-fail split, confounded verdicts, random networks and decisive set counts."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from voe.controls.builtin import builtin_controls
from voe.controls.confound import apply_confounding, confounders
from voe.controls.matrix import outcome_ok, specificity_matrix
from voe.controls.spec import Control
from voe.scoring.runs import Run
from voe.scoring.stats import holm, permutation_pvalue
from voe.scoring.verdict import CONFOUNDED, LEARNED, NOT_LEARNED, min_sets_decisive, verdict


def _run(nll: np.ndarray, n_sets: int, label: str = "m") -> Run:
    """Pairs: clip 2i possible, 2i+1 impossible; sets alternate visible/occluded."""
    rows = []
    for i in range(2 * n_sets):
        s = i // 2
        rows.append({"clip_id": f"c{i}", "concept": "X-v1", "set_id": f"x-{s:02d}", "set_kind": "pair",
                     "variant": "p", "role": "impossible" if i % 2 else "possible", "onset_frame": 1,
                     "visible_violation": bool(s % 2), "n_distractors": 0})
    return Run(None, {}, pd.DataFrame(rows), nll, label)


def test_constant_and_balanced_chance_cells_could_not_fail_the_rest_could():
    n = 10
    const = _run(np.ones((2 * n, 3)), n, "const")
    rng = np.random.default_rng(0)
    noisy = _run(rng.normal(size=(2 * n, 3)), n, "noisy")
    ctrls = [Control("const", "random-net", "m", default="chance"),
             Control("fb", "knowledge-free", "m", default="chance", invariant_to="F"),
             Control("fb2", "knowledge-free", "m", default="chance", invariant_to="F")]
    bal = pd.DataFrame({"concept": "X-v1", "set_id": [f"x-{s:02d}" for s in range(n)], "F": True})
    bal.loc[3, "F"] = False  # one set short of F balance: the F scorer could have failed
    m = specificity_matrix(ctrls, [const, noisy, noisy], n_boot=200, balance=bal)
    allrow = m[m["condition"] == "all"].set_index("control")
    assert allrow.loc["const", "could_fail"] == False  # noqa: E712 (a constant ties by construction)
    assert allrow.loc["fb", "could_fail"] == True  # noqa: E712
    cond = m[(m["control"] == "fb") & (m["condition"] != "all")].set_index("condition")
    assert cond.loc["occluded", "could_fail"] == False and cond.loc["visible", "could_fail"] == True  # noqa: E712
    assert cond.loc["occluded", "expected"] == "chance"  # inherited by verdict-carrying conditions


@pytest.mark.parametrize(("expect", "verdict_", "ok"), [("not-learned", LEARNED, False),
                                                        ("not-learned", "inconclusive", True),
                                                        ("not-learned", NOT_LEARNED, True)])
def test_not_learned_declarations(expect, verdict_, ok):
    assert outcome_ok(expect, verdict_, 0.6, 0.9) is ok


def test_min_sets_decisive_by_hand_and_a_perfect_score_then_is_learned():
    assert [min_sets_decisive(m) for m in (1, 8, 16, 24)] == [5, 8, 9, 9]  # 16 * 2**-9 < .05 < 16 * 2**-8
    for m in (8, 16):
        n = min_sets_decisive(m)
        p = holm(np.full(m, permutation_pvalue(np.ones(n))))
        assert verdict(1.0, 1.0, 1.0, p[0])[0] == LEARNED
        p = holm(np.full(m, permutation_pvalue(np.ones(n - 1))))
        assert verdict(1.0, 1.0, 1.0, p[0])[0] != LEARNED


def _matrix_row(control, family, acc, lo, hi, verdict_, expected, condition="all", concept="X-v1", p2=0.001):
    return {"control": control, "family": family, "concept": concept, "condition": condition,
            "carries_verdict": True, "accuracy": acc, "ci_low": lo, "ci_high": hi, "verdict": verdict_,
            "expected": expected, "p_two_sided": p2}


def test_confounded_when_a_knowledge_free_control_is_off_chance_either_way_or_a_reference_overreaches():
    m = pd.DataFrame([
        _matrix_row("height", "knowledge-free", 0.5, 0.3, 0.7, NOT_LEARNED, "chance", concept="A-v1"),
        _matrix_row("height", "knowledge-free", 0.0, 0.0, 0.1, NOT_LEARNED, "chance", concept="B-v1"),  # reversed
        _matrix_row("constvel", "physics-poor", 1.0, 1.0, 1.0, LEARNED, "not-learned", concept="C-v1"),
        _matrix_row("constvel", "physics-poor", 1.0, 1.0, 1.0, LEARNED, "pass", concept="A-v1"),  # declared
        _matrix_row("lesion", "lesion", 0.0, 0.0, 0.0, NOT_LEARNED, "pass", concept="A-v1"),  # not a confound
        _matrix_row("speed", "knowledge-free", 0.9, 0.8, 1.0, LEARNED, "chance", "visible", concept="D-v1"),
    ])
    m.loc[len(m)] = _matrix_row("speed", "knowledge-free", 0.0, 0.0, 0.0, NOT_LEARNED, "chance",
                                concept="F-v1", p2=0.25)  # three sets that happen to agree
    conf = confounders(m, no_balance={"E-v1"}).set_index(["concept", "condition"])
    assert not conf.loc[("F-v1", "all"), "confounded"]
    assert not conf.loc[("A-v1", "all"), "confounded"]
    assert conf.loc[("B-v1", "all"), "by"] == "height 0.00 [0.00, 0.10]"
    assert conf.loc[("C-v1", "all"), "confounded"] and conf.loc[("D-v1", "visible"), "confounded"]
    m = m[m["concept"] != "F-v1"]
    summary = pd.DataFrame({"model": "m", "concept": ["A-v1", "B-v1", "C-v1", "D-v1"],
                            "verdict": [LEARNED, LEARNED, NOT_LEARNED, LEARNED]})
    out = apply_confounding(summary, confounders(m)).set_index("concept")
    assert out["verdict"].tolist() == [LEARNED, CONFOUNDED, CONFOUNDED, CONFOUNDED]
    assert out.loc["B-v1", "raw_verdict"] == LEARNED and "visible: speed 0.90" in out.loc["D-v1", "confounded_by"]


def test_concepts_without_a_balanced_design_are_always_confounded():
    m = pd.DataFrame([_matrix_row("height", "knowledge-free", 0.5, 0.3, 0.7, NOT_LEARNED, "chance")])
    conf = confounders(m, no_balance={"X-v1"})
    assert conf["confounded"].all() and conf["by"].iloc[0] == "declares no balanced design"


def test_random_networks_are_ten_per_architecture_non_constant_and_differ_by_seed(tiny_probes):
    pytest.importorskip("torch")
    from voe.controls.random_nets import random_network
    from voe.io.probeset import load_probe_set

    nets = [c for c in builtin_controls(("random-net",))]
    for arch in ("mlp", "interaction", "pixel"):
        assert sum(c.args["arch"] == arch for c in nets) >= 10
    ps = load_probe_set(tiny_probes)
    batch = ps.batch(list(ps.index["clip_id"][:6]))
    for arch in ("mlp", "interaction", "pixel"):
        a, b = random_network(arch, 0), random_network(arch, 1)
        assert all(p.any() for p in a.weights().values() if p.ndim > 1), f"{arch} kept a zero layer"
        x, y = a.frame_nll(batch)[:, a.warmup:], b.frame_nll(batch)[:, b.warmup:]  # (B, T - warmup)
        assert np.isfinite(x).all() and x.std(0).mean() > 1e-3, f"{arch} is constant across clips"
        assert not np.allclose(x, y), f"{arch}: two seeds give the same function"


def test_random_networks_confound_only_models_of_their_own_class():
    from voe.controls.confound import scoped_confounders

    m = pd.DataFrame([_matrix_row("random-interaction-s0", "random-net", 1.0, 1.0, 1.0, LEARNED, "chance"),
                      _matrix_row("density", "knowledge-free", 0.5, 0.3, 0.7, NOT_LEARNED, "chance")])
    m["scope"] = ["voe.models.interaction:InteractionNet", ""]
    assert not confounders(m)["confounded"].any()
    scoped = scoped_confounders(m)
    summary = pd.DataFrame({"model": ["interaction", "oracle"], "concept": "X-v1", "verdict": LEARNED})
    out = apply_confounding(summary, confounders(m), scoped,
                            {"interaction": "voe.models.interaction:InteractionNet",
                             "oracle": "voe.models.oracle:PhysicsOracle"}).set_index("model")
    assert out.loc["interaction", "verdict"] == CONFOUNDED and out.loc["oracle", "verdict"] == LEARNED
    assert out.loc["interaction", "confounded_by"].startswith("random-interaction-s0 1.00")


def _quad_run(d_ab: float, d_ba: float, n_sets: int, label: str) -> Run:
    """Quadruplets whose per-frame surprise differs only at the return frame after the splice:
    AB by ``d_ab`` against B's frames, BA by ``d_ba`` against A's (``voe.scoring.halves``)."""
    from voe.scoring import halves as halves_mod

    T, rows, nll = 10, [], []
    for s in range(n_sets):
        for v in ("A", "B", "AB", "BA"):
            rows.append({"clip_id": f"c{s}{v}", "concept": "Q-v1", "set_id": f"q-{s:02d}",
                         "set_kind": "quadruplet", "variant": v,
                         "role": "impossible" if len(v) == 2 else "possible", "onset_frame": 1,
                         "visible_violation": False, "n_distractors": 0})
            x = np.ones(T)
            x[7] += {"AB": d_ab, "BA": d_ba}.get(v, 0.0)
            nll.append(x)
    sha = f"sha-{label}"
    halves_mod._SIDES[sha] = {f"q-{s:02d}": np.array([True] * 5 + [False] * 5) for s in range(n_sets)}
    meta = {"probes": {"manifest_sha256": sha, "path": "none"}, "model": {"name": label}}
    return Run(None, meta, pd.DataFrame(rows), np.array(nll), label)


def test_on_spliced_quadruplets_a_control_confounds_through_the_halves_not_the_sum():
    n = 12
    fading = _quad_run(+3.0, -1.0, n, "fading")  # sum right on every set, each half right once
    knows = _quad_run(+2.0, +1.0, n, "knows")  # both halves right: a memory that passes the verdict
    ctrls = [Control("fading", "knowledge-free", "m", default="chance"),
             Control("knows", "knowledge-free", "m", default="chance")]
    m = specificity_matrix(ctrls, [fading, knows], n_boot=200)
    rows = m[m["condition"] == "all"].set_index("control")
    assert (rows["verdict_stat"] == "halves").all()
    assert rows.loc["fading", "accuracy"] == 1.0 and rows.loc["fading", "halves"] == 0.5
    assert not confounders(m[m["control"] == "fading"])["confounded"].any()
    conf = confounders(m[m["control"] == "knows"])
    assert conf["confounded"].all() and conf["by"].iloc[0].startswith("knows halves 1.00")
    # a cell of pairs keeps the sum as its statistic: there the sum alone carries the verdict
    pairs = specificity_matrix([Control("p", "knowledge-free", "m", default="chance")],
                               [_run(np.r_[np.zeros((1, 3)), np.ones((1, 3))].repeat(n, 0).reshape(2, n, 3)
                                     .transpose(1, 0, 2).reshape(2 * n, 3), n)], n_boot=200)
    assert (pairs["verdict_stat"] == "sum").all() and confounders(pairs)["confounded"].all()
