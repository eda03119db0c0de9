"""Random networks randomize every parameter of every registered learned architecture.

What must hold: after ``random_network(arch, seed)`` no parameter (or buffer) is all zero, and none
is the same for two seeds. A parameter that stays at its initial value (a closed gate, a typical
state, a zero output layer) would make every random network of the architecture share the same
fixed part, so the control would sample "this architecture with that part fixed", not "any
function the architecture could compute before training" (issue #11: random v2 networks kept the
state-head gates closed and tied every hidden splice by construction).
"""

from __future__ import annotations

import pytest

torch = pytest.importorskip("torch")

from voe.controls.random_nets import random_network  # noqa: E402
from voe.models import MODELS  # noqa: E402

LEARNED = [k for k in MODELS.ids() if MODELS.meta(k).get("learned")]


def test_every_learned_architecture_is_covered():
    """Every registered learned architecture gets random-network controls (a new one without them
    would be judged without its untrained baseline), and every control names a registered one."""
    from voe.controls.builtin import LEARNED_ARCHS

    families = {k.split("-v")[0] for k in LEARNED}
    assert families <= set(LEARNED_ARCHS), f"no random-network controls for {sorted(families - set(LEARNED_ARCHS))}"
    assert set(LEARNED_ARCHS) <= families, f"random-network controls for unregistered {set(LEARNED_ARCHS) - families}"


@pytest.mark.parametrize("arch", LEARNED)
def test_random_networks_randomize_every_parameter(arch):
    a, b = random_network(arch, 0).net.state_dict(), random_network(arch, 1).net.state_dict()
    fixed = [k for k, p in a.items() if p.is_floating_point() and (not p.any() or torch.equal(p, b[k]))]
    assert not fixed, f"{arch}: random_network leaves {fixed} at a value shared by seeds 0 and 1"


@pytest.mark.parametrize("arch", ["interaction-v2", "interaction-v3"])
def test_head_draws_stay_in_their_declared_ranges(arch):
    """Gates (v2) in [0, 1]; the v3 map like a 13-input linear layer; offsets in [-1, 1]."""
    for seed in range(5):
        head = random_network(arch, seed).net.head
        g = head.gates().detach()
        if arch == "interaction-v2":
            assert 0.0 <= float(g.min()) and float(g.max()) <= 1.0 and float(g.max()) > 0.5
        else:
            assert float(g.abs().max()) <= 13 ** -0.5 + 1e-6 and float(g.abs().max()) > 0.1
        assert float((head.LV_GAIN * head.lv_bias).detach().abs().max()) <= 1.0
        assert -1.0 <= float(head.shape_gain.detach()) <= 1.0
