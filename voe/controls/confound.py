"""When a probe cannot tell: confounded concepts and conditions, from the control cells.

Why: "model M learned X" only means something if nothing that lacks X separates the probe's
clips as well. So wherever, on the same probe set, a knowledge-free control is off chance (either
direction: a reversed statistic is a perfect one negated; its 95% CI excludes 0.5 *and* the
two-sided sign-flip test rejects chance at ``ALPHA``, so that three sets that happen to agree do
not condemn a probe) or a physics-poor reference is learned
beyond its declared knowledge, every model's verdict there becomes *confounded*, shown next to
the control that did it (``voe.scoring.verdict.CONFOUNDED_RULE``). Concepts that declare no
balanced design are confounded whatever the controls do. Works for any concept in a probe set,
user-made ones included: it reads only the matrix.
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
    return f"{r.control} {r.accuracy:.2f} [{r.ci_low:.2f}, {r.ci_high:.2f}]"


def confounders(matrix: pd.DataFrame, no_balance: Iterable[str] = ()) -> pd.DataFrame:
    """Per concept x condition that carries a verdict (``all`` = the pooled verdict sets): the
    controls that confound it. Columns: concept, condition, confounded, by."""
    m = matrix[(matrix["condition"] == "all") | matrix["carries_verdict"].astype(bool)]
    off = ~((m["ci_low"] <= 0.5) & (0.5 <= m["ci_high"])) & m.get("p_two_sided", pd.Series(0.0, index=m.index)).lt(ALPHA)
    kf = m["family"].isin(KNOWLEDGE_FREE) & off
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


def confounded_concepts(conf: pd.DataFrame) -> dict[str, str]:
    """concept -> why, for concepts confounded on their pooled sets or on any verdict condition."""
    out: dict[str, list[str]] = {}
    for r in conf[conf["confounded"]].itertuples():
        out.setdefault(r.concept, []).append(r.by if r.condition == "all" else f"{r.condition}: {r.by}")
    return {c: " | ".join(dict.fromkeys(v)) for c, v in out.items()}


def apply_confounding(summary: pd.DataFrame, conf: pd.DataFrame) -> pd.DataFrame:
    """Summary (model x concept) with ``verdict`` confounded where the probe cannot tell; the rule's
    own verdict moves to ``raw_verdict`` and the control that confounds it to ``confounded_by``."""
    why = confounded_concepts(conf)
    out = summary.copy()
    out["raw_verdict"] = out["verdict"]
    out["confounded_by"] = [why.get(c, "") for c in out["concept"]]
    out.loc[out["confounded_by"] != "", "verdict"] = CONFOUNDED
    return out
