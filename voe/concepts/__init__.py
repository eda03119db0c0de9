"""The concept registry. Built-in registrations only; each lives in its own module."""

from __future__ import annotations

from voe.registry import Registry

CONCEPTS: Registry = Registry("concept")

CONCEPTS.register("Permanence-v2", "voe.concepts.permanence:Permanence")
CONCEPTS.register("Continuity-v2", "voe.concepts.continuity:Continuity")
CONCEPTS.register("Unchangeableness-v3", "voe.concepts.unchangeableness:Unchangeableness")
CONCEPTS.register("Solidity-v3", "voe.concepts.solidity:Solidity")
CONCEPTS.register("Inertia-v1", "voe.concepts.inertia:Inertia")
CONCEPTS.register("Gravity-v4", "voe.concepts.gravity:Gravity")
CONCEPTS.register("Collision-v4", "voe.concepts.collision:Collision")
CONCEPTS.register("Energy-v6", "voe.concepts.energy:Energy")

#: The suites ``voe probes generate --suite`` knows, by concept name (latest version is used).
SUITES: dict[str, tuple[str, ...]] = {
    "core": ("permanence", "continuity", "unchangeableness", "solidity", "inertia", "gravity",
             "collision", "energy"),
}


def get_concept(name: str):
    """Instantiate a registered concept by id or name (``Permanence-v1``, ``permanence``)."""
    return CONCEPTS.get(name)()
