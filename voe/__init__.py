"""voe: violation-of-expectation evaluation for learned physics simulators.

The public API is re-exported lazily so that ``import voe`` (and ``voe --help``) stays instant.
"""

from __future__ import annotations

from typing import Any

__version__ = "0.1.0"

_LAZY = {
    "load_probe_set": "voe.io.probeset:load_probe_set",
    "ProbeSet": "voe.io.probeset:ProbeSet",
    "Batch": "voe.io.batch:Batch",
    "Model": "voe.models.protocol:Model",
    "check_concept": "voe.concepts.check:check_concept",
    "check_model": "voe.models.check:check_model",
    "score_probe_set": "voe.scoring.score:score_probe_set",
    "score_surprises": "voe.scoring.external:score_surprises",
    "CONCEPTS": "voe.concepts:CONCEPTS",
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from voe.registry import load_ref

        return load_ref(_LAZY[name])
    raise AttributeError(f"module 'voe' has no attribute {name!r}")
