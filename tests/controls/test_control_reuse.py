"""A stored control run stands in for a control only if the same code made it, for the same
control, on the same probe set (a stale random network would silently drop its confounds)."""

from __future__ import annotations

from voe.controls.run import stale_reason
from voe.controls.spec import Control
from voe.models.constvel import ConstantVelocity
from voe.scoring.cache import class_code_sha256, code_sha256

CLS = f"{ConstantVelocity.__module__}:{ConstantVelocity.__qualname__}"


def _meta(**model) -> dict:
    base = {"ref": "constvel", "class": CLS, "args": {"noise": 0.1}, "code_sha256": class_code_sha256(ConstantVelocity)}
    return {"probes": {"manifest_sha256": "m1"}, "model": {**base, **model}}


def test_a_run_of_this_code_for_this_control_is_reused_and_anything_else_is_not():
    ctrl = Control("cv", "physics-poor", "constvel", args={"noise": 0.1})
    assert stale_reason(_meta(), ctrl, "m1") == ""
    assert "probe set" in stale_reason(_meta(), ctrl, "m2")
    assert "made by" in stale_reason(_meta(args={"noise": 0.2}), ctrl, "m1")
    assert "made by" in stale_reason(_meta(ref="framecopy"), ctrl, "m1")
    assert "other code" in stale_reason(_meta(code_sha256="0" * 64), ctrl, "m1")
    assert "other code" in stale_reason(_meta(code_sha256=None), ctrl, "m1")  # runs stored before the key
    assert "other code" in stale_reason(_meta(**{"class": "voe.models.gone:Nothing"}), ctrl, "m1")


def test_the_class_key_is_the_key_a_scorer_records():
    assert class_code_sha256(ConstantVelocity) == code_sha256(object.__new__(ConstantVelocity))
