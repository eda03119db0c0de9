"""Random networks: a learned architecture with random weights everywhere, output layers included.

Why: the learned models start with zero output layers, so an untrained one is a constant (it
ties every set by construction and is no evidence of anything). A random network with random,
non-zero output layers is a random, non-constant function of what it sees; it knows no physics,
so it must sit at chance on every concept. Many seeds per architecture sample "any function this
architecture could compute before training"; one that lands off chance shows the probe gives its
answer away to functions of that shape.
"""

from __future__ import annotations

from typing import Any


def random_network(arch: str, seed: int = 0, **kw: Any) -> Any:
    """The registered learned model ``arch`` with every weight random (seeded), never trained."""
    from voe.models.loading import load_model

    model = load_model(arch, {"seed": int(seed), **kw})
    model.randomize_outputs(int(seed) + 7919)  # a stream apart from the body's torch seed
    model.name = f"random-{arch}-s{seed}"
    return model
