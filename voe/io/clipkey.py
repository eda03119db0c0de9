"""Opaque keys for clips and matched sets, shared by the blind harness and the clip export.

Why: a clip id such as ``permanence-0001-AB`` names its role, and a model (or an outside tool)
that reads it can score 1.00 without any physics. Everything that leaves voe's own code (a
``Batch`` handed to a model, an exported file name, a surprise table) carries these keys
instead. They are deterministic (same probe set, same keys), so stored results and outside
surprise tables can be joined back to the index, but they reveal nothing about role or order.
"""

from __future__ import annotations

import hashlib

#: Length of a key in hex characters (64 bits: no collisions at any realistic probe-set size).
KEY_CHARS = 16


def clip_key(manifest_sha256: str, clip_id: str) -> str:
    """Opaque key of one clip: a hash of the probe set's manifest sha256 and the clip id."""
    return hashlib.sha256(f"voe-clip:{manifest_sha256}:{clip_id}".encode()).hexdigest()[:KEY_CHARS]


def set_key(manifest_sha256: str, set_id: str) -> str:
    """Opaque key of one matched set (same scheme as :func:`clip_key`, another namespace)."""
    return hashlib.sha256(f"voe-set:{manifest_sha256}:{set_id}".encode()).hexdigest()[:KEY_CHARS]
