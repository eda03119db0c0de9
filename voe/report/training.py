"""How each scored model was trained, as the report states it (from the runs' stored records only).

Why: a learned model's verdicts are only as good as its training. ``voe train`` stops at a wall-time
cap (``--minutes``) when the machine is slow or loaded, and records ``time_capped`` in the checkpoint;
``voe score`` copies the record into ``run.json`` (``model.training``). A capped model is
under-trained by an amount that depends on the machine, so the report names it next to the
Models table instead of presenting its verdicts as the architecture's.
"""

from __future__ import annotations

from collections.abc import Sequence

from voe.scoring.runs import Run


def training_text(record: dict | None) -> str:
    """One cell: ``"638 of 700 steps (time cap); val NLL 18.90"``, ``"calibrated on 64 clips"`` or ``"-"``."""
    if not isinstance(record, dict) or not record:  # absent, or a run.json written by other tools
        return "-"
    if "n_calibration" in record:
        text = f"calibrated on {record['n_calibration']} clips"
    elif "steps" in record:
        budget = record.get("steps_budget")
        text = f"{record['steps']} of {budget} steps" if budget is not None else f"{record['steps']} steps"
        if record.get("time_capped"):
            text += " (time cap)"
    else:
        return "-"
    nll = record.get("val_nll")
    return text + (f"; val NLL {nll:.2f}" if isinstance(nll, int | float) else "")


def capped_note(runs: Sequence[Run]) -> str | None:
    """A warning naming every model whose training the time cap stopped, or ``None`` if none was."""
    capped = [(r.label, r.meta["model"].get("training")) for r in runs]
    capped = [(label, t) for label, t in capped if isinstance(t, dict) and t.get("time_capped") is True]
    if not capped:
        return None
    names = "; ".join(f"`{label}` after {t.get('steps')} of {t.get('steps_budget')} steps" for label, t in capped)
    return ("**Warning: under-trained model(s).** Training stopped at its wall-time cap before the step "
            f"budget: {names}. Such weights depend on how fast and how loaded the training machine was, so "
            "these verdicts are not the architecture's: train again on an idle machine or with a larger "
            "`voe train --minutes` cap before comparing.")
