"""When a probe cannot tell: confounded concepts and conditions, from the control cells.

Why: "model M learned X" only means something if nothing that lacks X separates the probe's
clips as well. So wherever, on the same probe set, a knowledge-free control is off chance (either
direction: a reversed statistic is a perfect one negated; its 95% CI excludes 0.5 *and* the
two-sided sign-flip test rejects chance at ``ALPHA``, so that three sets that happen to agree do
not condemn a probe; on spliced quadruplets this is read on the halves, the statistic that
carries the verdict there, see ``off_chance``) or a physics-poor reference is learned
beyond its declared knowledge, every model's verdict there becomes *confounded*, shown next to
the control that did it (``voe.scoring.verdict.CONFOUNDED_RULE``). Concepts that declare no
balanced design are confounded whatever the controls do. Works for any concept in a probe set,
user-made ones included: it reads only the matrix.

Random networks are scoped to their architecture (the model class, ``scope`` in the matrix). A
random network reads its architecture's own input code (for ``mlp``: per-slot memory of hidden
objects and the constant-velocity guess; ``interaction`` carries hidden objects only by its own
learned predictions, so a random one forgets them), so when random readouts of that code separate
a probe's clips, what it shows is that *models of that architecture* can pass the probe without
learning anything: their verdicts there are confounded. A model of another architecture (the oracle, the pixel
model) does not read that code, and the probe's bytes stay balanced for it.
"""

from __future__ import annotations

from collections.abc import Iterable

import pandas as pd

from voe.controls.spec import KNOWLEDGE_FREE, PHYSICS_POOR
from voe.scoring.verdict import ALPHA, CONFOUNDED, LEARNED

NO_BALANCE = "declares no balanced design"


def no_balanced_design(index: pd.DataFrame) -> set[str]:
    """Concepts of a probe-set index whose sets are flagged ``confounded`` (the concept declares
    no balanced design; recorded at generation, so reports need not import the concepts)."""
    if "confounded" not in index.columns:
        return set()
    return set(index.loc[index["confounded"].fillna(False).astype(bool), "concept"].astype(str))


def _cell_text(r) -> str:
    if getattr(r, "verdict_stat", "sum") == "halves":
        return f"{r.control} halves {r.halves:.2f} [{r.halves_ci_low:.2f}, {r.halves_ci_high:.2f}] (sum {r.accuracy:.2f})"
    return f"{r.control} {r.accuracy:.2f} [{r.ci_low:.2f}, {r.ci_high:.2f}]"


def _outside(lo: pd.Series, hi: pd.Series, p2: pd.Series) -> pd.Series:
    return ~((lo <= 0.5) & (0.5 <= hi)) & p2.lt(ALPHA)


def off_chance(m: pd.DataFrame) -> pd.Series:
    """Matrix cells whose control is off chance, either way, on the statistic that carries the
    cell's verdict.

    That is the sum's accuracy, except on cells made only of spliced quadruplets
    (``verdict_stat == 'halves'``), where it is the halves accuracy: there a model is *learned*
    only if its halves are (``voe.scoring.verdict.HALVES_RULE``), and a set whose two halves are
    both right has its sum right too, so the halves decide. A memory whose cost only grows (or
    only fades) with the time an object was hidden moves the sum off chance but leaves the
    halves at exactly 0.5 on every set; such a control shows that the *sum* can be gamed, which
    the halves rule already stops, not that a model passing the halves lacks the concept.
    """
    p2 = m["p_two_sided"] if "p_two_sided" in m.columns else pd.Series(0.0, index=m.index)
    off = _outside(m["ci_low"], m["ci_high"], p2)
    if "verdict_stat" not in m.columns:
        return off
    hv = m["verdict_stat"].eq("halves")
    return off.where(~hv, _outside(m["halves_ci_low"], m["halves_ci_high"], m["halves_p_two_sided"]))


def _verdict_cells(matrix: pd.DataFrame) -> pd.DataFrame:
    return matrix[(matrix["condition"] == "all") | matrix["carries_verdict"].astype(bool)]


def _scope(m: pd.DataFrame) -> pd.Series:
    return m["scope"].fillna("").astype(str) if "scope" in m.columns else pd.Series("", index=m.index)


def confounders(matrix: pd.DataFrame, no_balance: Iterable[str] = ()) -> pd.DataFrame:
    """Per concept x condition that carries a verdict (``all`` = the pooled verdict sets): the
    controls that confound it for every model (scoped controls excluded, see
    ``scoped_confounders``). Columns: concept, condition, confounded, by."""
    m = _verdict_cells(matrix)
    kf = m["family"].isin(KNOWLEDGE_FREE) & off_chance(m) & _scope(m).eq("")
    pp = m["family"].isin(PHYSICS_POOR) & m["verdict"].eq(LEARNED) & ~m["expected"].isin(("pass", "none"))
    bad = m[kf | pp]
    nb = set(no_balance)
    rows = []
    for concept, cond in m[["concept", "condition"]].drop_duplicates().sort_values(["concept", "condition"]).itertuples(index=False):
        by = [_cell_text(r) for r in bad[(bad["concept"] == concept) & (bad["condition"] == cond)].itertuples()]
        if concept in nb:
            by.insert(0, NO_BALANCE)
        rows.append({"concept": concept, "condition": cond, "confounded": bool(by), "by": "; ".join(by)})
    return pd.DataFrame(rows, columns=["concept", "condition", "confounded", "by"])


def scoped_confounders(matrix: pd.DataFrame) -> dict[str, dict[str, str]]:
    """model class -> {concept: why} from its random networks that are off chance."""
    m = _verdict_cells(matrix)
    m = m[m["family"].isin(KNOWLEDGE_FREE) & off_chance(m) & _scope(m).ne("")]
    out: dict[str, dict[str, list[str]]] = {}
    for r in m.itertuples():
        where = "" if r.condition == "all" else f"{r.condition}: "
        out.setdefault(str(r.scope), {}).setdefault(r.concept, []).append(where + _cell_text(r))
    return {a: {c: "; ".join(v) for c, v in d.items()} for a, d in out.items()}


def confounded_concepts(conf: pd.DataFrame) -> dict[str, str]:
    """concept -> why, for concepts confounded on their pooled sets or on any verdict condition."""
    out: dict[str, list[str]] = {}
    for r in conf[conf["confounded"]].itertuples():
        out.setdefault(r.concept, []).append(r.by if r.condition == "all" else f"{r.condition}: {r.by}")
    return {c: " | ".join(dict.fromkeys(v)) for c, v in out.items()}


def apply_confounding(summary: pd.DataFrame, conf: pd.DataFrame,
                      scoped: dict[str, dict[str, str]] | None = None,
                      arch_of: dict[str, str] | None = None) -> pd.DataFrame:
    """Summary (model x concept) with ``verdict`` confounded where the probe cannot tell; the rule's
    own verdict moves to ``raw_verdict`` and the control that confounds it to ``confounded_by``.
    ``scoped`` (``scoped_confounders``) applies to models whose class ``arch_of[model]`` is the
    scope."""
    why = confounded_concepts(conf)
    scoped, arch_of = scoped or {}, arch_of or {}
    out = summary.copy()
    out["raw_verdict"] = out["verdict"]
    out["confounded_by"] = [
        " | ".join(x for x in (why.get(c, ""), scoped.get(arch_of.get(m, ""), {}).get(c, "")) if x)
        for m, c in zip(out["model"], out["concept"], strict=True)]
    out.loc[out["confounded_by"] != "", "verdict"] = CONFOUNDED
    return out
