"""voe: violation-of-expectation evaluation for learned physics simulators."""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
