"""The score cache is keyed by the code that computes surprise, not only by the version string."""

from __future__ import annotations

import importlib.util
import sys

from voe.scoring.cache import ScoreCache, cache_key, code_sha256


def _load(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


def test_editing_a_user_scorer_changes_its_cache_directory(tmp_path):
    src = tmp_path / "my_scorer_mod.py"
    src.write_text("class Scorer:\n    def surprise(self):\n        return 1.0\n")
    before = code_sha256(_load(src, "my_scorer_mod").Scorer())
    again = code_sha256(_load(src, "my_scorer_mod").Scorer())
    src.write_text("class Scorer:\n    def surprise(self):\n        return 2.0\n")
    after = code_sha256(_load(src, "my_scorer_mod").Scorer())
    assert before == again and before != after
    fields = {"model": "my_scorer_mod:Scorer", "seed": 0}
    a = ScoreCache(tmp_path / "c", {**fields, "code_sha256": before})
    b = ScoreCache(tmp_path / "c", {**fields, "code_sha256": after})
    assert a.dir != b.dir and cache_key({**fields, "code_sha256": before}) == a.dir.name


def test_builtin_models_share_the_package_fingerprint():
    from voe.models.constvel import ConstantVelocity as ConstVel
    from voe.models.framecopy import FrameCopy

    assert code_sha256(ConstVel()) != code_sha256(FrameCopy())  # each adds its own file
    assert len(code_sha256(ConstVel())) == 64
