"""Write ``gap.json`` atomically, with provenance.

Why: a half-written result file looks like a result. Files are written to a temporary path in
the same directory and renamed into place. Provenance (voe and package versions, seed, sha256
of the inputs) makes a diagnosis traceable to exactly what produced it.
"""

from __future__ import annotations

import platform
from importlib import metadata
from pathlib import Path
from typing import Any

from voe.io import jsonio
from voe.io.atomic import atomic_write_bytes
from voe.io.provenance import sha256_file

PACKAGES = ("numpy", "scipy", "pandas", "pymunk", "typer", "matplotlib")


def atomic_write(path: Path, data: str | bytes) -> None:
    """Write ``data`` (text as UTF-8) to ``path`` via a temporary file and ``os.replace``
    (``voe.io.atomic``, shared with the probe and score writers)."""
    atomic_write_bytes(Path(path), data.encode("utf-8") if isinstance(data, str) else data)


def sha256(path: str | Path) -> str:
    """sha256 of a file's bytes (``voe.io.provenance.sha256_file``)."""
    return sha256_file(Path(path))


def provenance(seed: int, inputs: dict[str, str | Path], config: Any = None) -> dict:
    """Versions, seed and input checksums."""
    import voe

    versions = {}
    for p in PACKAGES:
        try:
            versions[p] = metadata.version(p)
        except metadata.PackageNotFoundError:
            versions[p] = None
    return {"voe_version": voe.__version__, "python": platform.python_version(), "packages": versions,
            "seed": seed, "inputs": {k: {"path": str(v), "sha256": sha256(v)} for k, v in inputs.items()},
            "config": repr(config) if config is not None else None}


def write_json(path: Path, payload: dict) -> None:
    atomic_write(path, jsonio.dumps(payload, indent=2) + "\n")
