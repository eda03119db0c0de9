import pytest

from voe.errors import UnknownNameError
from voe.registry import Registry, load_ref, split_id


def make():
    r = Registry("thing")
    r.register("Alpha-v1", "json:dumps")
    r.register("Alpha-v2", "json:loads")
    r.register("Beta-v1", 42)
    return r


def test_versions_resolve_to_newest_and_exact():
    r = make()
    assert r.resolve("alpha") == "Alpha-v2"
    assert r.resolve("Alpha-v1") == "Alpha-v1"
    assert r.get("Beta") == 42


def test_lazy_ref_is_imported_on_get():
    import json

    assert make().get("Alpha-v1") is json.dumps


def test_typo_suggests_close_names():
    with pytest.raises(UnknownNameError, match="did you mean 'Alpha"):
        make().get("Alpah")


def test_unknown_version_is_an_error():
    with pytest.raises(UnknownNameError):
        make().resolve("Beta-v3")


def test_duplicate_registration_refused():
    r = make()
    with pytest.raises(ValueError):
        r.register("Beta-v1", 1)


def test_split_id_and_load_ref_errors():
    assert split_id("Permanence-v12") == ("Permanence", 12)
    assert split_id("plain") == ("plain", None)
    with pytest.raises(UnknownNameError, match="no attribute"):
        load_ref("json:nope")
    with pytest.raises(UnknownNameError, match="cannot import"):
        load_ref("no_such_module_xyz:thing")
