"""The concept registry. Built-in registrations only; each lives in its own module."""

from __future__ import annotations

from voe.registry import Registry

CONCEPTS: Registry = Registry("concept")

CONCEPTS.register("Permanence-v1", "voe.concepts.permanence:Permanence")

#: The suites ``voe probes generate --suite`` knows, by concept name (latest version is used).
SUITES: dict[str, tuple[str, ...]] = {
    "core": ("permanence", "continuity", "unchangeableness", "solidity", "inertia", "gravity",
             "collision", "energy"),
}


def get_concept(name: str):
    """Instantiate a registered concept by id or name (``Permanence-v1``, ``permanence``)."""
    return CONCEPTS.get(name)()
